#include "services/engines/ga/ga_engine.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "absl/strings/str_cat.h"
#include "services/core/byte_codec.h"
#include "services/core/keyed_rng.h"
#include "services/engines/ga/ga_operators.h"

namespace gaitforge::engines::ga {

using core::KeyedRng;
using core::Purpose;

absl::Status ValidateGaConfig(const GaConfig& c) {
  if (c.population < 2 || c.population > 100000)
    return absl::InvalidArgumentError(
        absl::StrCat("population = ", c.population, " is out of range [2, 100000]"));
  if (c.generations < 1 || c.generations > 100000)
    return absl::InvalidArgumentError(
        absl::StrCat("generations = ", c.generations, " is out of range [1, 100000]"));
  if (c.elite < 0 || c.elite >= c.population)
    return absl::InvalidArgumentError(absl::StrCat(
        "ga.elite = ", c.elite, " is out of range [0, population - 1 = ", c.population - 1, "]"));
  if (!(c.mutation_rate >= 0.0 && c.mutation_rate <= 1.0))
    return absl::InvalidArgumentError(
        absl::StrCat("ga.mutation_rate = ", c.mutation_rate, " is out of range [0, 1]"));
  if (c.selection != "roulette" && c.selection != "tournament")
    return absl::InvalidArgumentError(
        absl::StrCat("ga.selection = '", c.selection, "' is not one of roulette, tournament"));
  if (c.crossover != "one_point" && c.crossover != "blend")
    return absl::InvalidArgumentError(
        absl::StrCat("ga.crossover = '", c.crossover, "' is not one of one_point, blend"));
  if (c.mutation != "reinit" && c.mutation != "gaussian")
    return absl::InvalidArgumentError(
        absl::StrCat("ga.mutation = '", c.mutation, "' is not one of reinit, gaussian"));
  if (c.stop_fitness && !std::isfinite(*c.stop_fitness))
    return absl::InvalidArgumentError(
        absl::StrCat("ga.stop_fitness = ", *c.stop_fitness, " is not a finite number"));
  return ValidateBounds(c.bounds);
}

GaEngine::GaEngine(const GaConfig& config) : config_(config) {}

absl::StatusOr<std::unique_ptr<GaEngine>> GaEngine::Create(const GaConfig& config) {
  if (auto s = ValidateGaConfig(config); !s.ok()) return s;
  std::unique_ptr<GaEngine> engine(new GaEngine(config));
  engine->InitialPopulation();
  return engine;
}

void GaEngine::InitialPopulation() {
  candidates_.clear();
  for (int m = 0; m < config_.population; ++m) {
    KeyedRng rng(config_.seed, 0, m, Purpose::kInit);
    Candidate c;
    c.member = m;
    c.origin_generation = 0;
    c.origin_member = m;
    c.genes.resize(config_.bounds.size());
    for (size_t i = 0; i < c.genes.size(); ++i)
      c.genes[i] = rng.Uniform(config_.bounds.lo[i], config_.bounds.hi[i]);
    candidates_.push_back(std::move(c));
  }
}

bool GaEngine::ReachedStopFitness(const std::vector<Ranked>& hof) const {
  if (!config_.stop_fitness || hof.empty()) return false;
  const Evaluation& best = hof.front().eval;
  return best.valid && best.violation <= 0.0 && best.fitness >= *config_.stop_fitness;
}

std::string GaEngine::StopReason() const {
  if (ReachedStopFitness(hof_))
    return absl::StrCat("GA reached stop_fitness ", *config_.stop_fitness, " in generation ",
                        generation_ - 1);
  return "";
}

int GaEngine::CrossoverPoint(int g) const {
  const int n_genes = static_cast<int>(config_.bounds.size());
  if (n_genes < 2) return 0;
  KeyedRng rng(config_.seed, g, 0, Purpose::kCrossover);
  return static_cast<int>(rng.UniformInt(1, n_genes - 1));
}

absl::Status GaEngine::Tell(const std::vector<Evaluation>& evals) {
  if (Done()) return absl::FailedPreconditionError("GA: Tell after the last generation");
  if (static_cast<int>(evals.size()) != config_.population)
    return absl::InvalidArgumentError(absl::StrCat("GA: Tell got ", evals.size(),
                                                   " evaluations, expected ",
                                                   config_.population));
  for (size_t m = 0; m < evals.size(); ++m) {
    if (evals[m].valid && !std::isfinite(evals[m].fitness))
      return absl::InvalidArgumentError(
          absl::StrCat("GA: member ", m, " is valid with non-finite fitness"));
  }
  std::vector<int> order(evals.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return RanksBefore(evals[a], a, evals[b], b); });

  hof_.clear();
  // The hall of fame reports at least the best member even with elite = 0: the best
  // distinct genotypes (a copy, or the same gait at another phase, is left out).
  const size_t hof_size = static_cast<size_t>(std::max(config_.elite, 1));
  for (size_t r = 0; r < order.size() && hof_.size() < hof_size; ++r) {
    const Candidate& c = candidates_[order[r]];
    bool copy = false;
    for (const Ranked& h : hof_) copy = copy || SameGenotype(c.genes, h.genes, config_.bounds);
    if (!copy) hof_.push_back(Ranked{c.origin_generation, c.origin_member, c.genes, evals[order[r]]});
  }
  ++generation_;
  if (Done()) {
    candidates_.clear();
    return absl::OkStatus();
  }
  Breed(evals, order);
  return absl::OkStatus();
}

void GaEngine::Breed(const std::vector<Evaluation>& evals, const std::vector<int>& order) {
  const int g = generation_;  // the generation being created
  // Two population buffers swap roles each generation, so breeding reuses their memory.
  std::vector<Candidate>& next = spare_;
  next.resize(config_.population);
  for (int r = 0; r < config_.elite; ++r) {
    const Candidate& parent = candidates_[order[r]];
    Candidate& c = next[r];
    c.member = r;
    c.genes.assign(parent.genes.begin(), parent.genes.end());
    c.known = evals[order[r]];
    c.origin_generation = parent.origin_generation;
    c.origin_member = parent.origin_member;
  }
  const bool roulette = config_.selection == "roulette", blend = config_.crossover == "blend";
  const std::vector<double> cumulative = roulette ? Cumulative(RouletteWeights(evals)) : std::vector<double>();
  const int n = blend ? 0 : CrossoverPoint(g);
  for (int first = config_.elite; first < config_.population; first += 2) {
    KeyedRng select(config_.seed, g, first, Purpose::kSelect);
    const auto pick = [&] {
      return roulette ? RouletteSelectCumulative(cumulative, select)
                      : TournamentSelect(evals, kTournamentSize, select);
    };
    std::vector<double> a = candidates_[pick()].genes;
    std::vector<double> b = candidates_[pick()].genes;
    if (blend) {
      KeyedRng cross(config_.seed, g, first, Purpose::kCrossover);
      BlendCrossover(a, b, config_.bounds, kBlendRate, kBlendAlpha, cross);
    } else {
      // Child 0 takes b's first n genes and a's rest; child 1 the other way round.
      SwapPrefix(a, b, n);
    }
    for (int k = 0; k < 2 && first + k < config_.population; ++k) {
      Candidate& c = next[first + k];
      c.member = first + k;
      c.genes = k == 0 ? a : b;
      KeyedRng mutate(config_.seed, g, c.member, Purpose::kMutate);
      if (config_.mutation == "gaussian") {
        MutateGaussian(c.genes, config_.bounds, config_.mutation_rate, kGaussianSdFraction, mutate);
      } else {
        MutateReinit(c.genes, config_.bounds, config_.mutation_rate, mutate);
      }
      c.known.reset();
      c.origin_generation = g;
      c.origin_member = c.member;
    }
  }
  candidates_.swap(spare_);
}

namespace {
constexpr uint32_t kStateMagic = 0x32414147;  // "GAA2": evaluations carry a violation

}  // namespace

std::string GaEngine::SaveState() const {
  core::ByteWriter w;
  w.U32(kStateMagic);
  w.U64(config_.seed);
  w.U32(config_.population);
  w.U32(config_.generations);
  w.U32(config_.elite);
  w.F64(config_.mutation_rate);
  w.F64s(config_.bounds.lo);
  w.F64s(config_.bounds.hi);
  w.U32(generation_);
  w.U64(candidates_.size());
  for (const auto& c : candidates_) {
    w.U32(c.member);
    w.F64s(c.genes);
    w.U32(c.known ? 1 : 0);
    if (c.known) WriteEvaluation(w, *c.known);
    w.U32(c.origin_generation);
    w.U32(c.origin_member);
  }
  WriteRanked(w, hof_);
  return w.data();
}

absl::Status GaEngine::LoadState(std::string_view state) {
  core::ByteReader r(state);
  if (r.U32() != kStateMagic) return absl::DataLossError("GA state: wrong magic number");
  GaConfig c;
  c.seed = r.U64();
  c.population = static_cast<int>(r.U32());
  c.generations = static_cast<int>(r.U32());
  c.elite = static_cast<int>(r.U32());
  c.mutation_rate = r.F64();
  c.bounds.lo = r.F64s();
  c.bounds.hi = r.F64s();
  if (c.seed != config_.seed || c.population != config_.population ||
      c.generations != config_.generations || c.elite != config_.elite ||
      c.mutation_rate != config_.mutation_rate || c.bounds.lo != config_.bounds.lo ||
      c.bounds.hi != config_.bounds.hi)
    return absl::FailedPreconditionError("GA state belongs to a different configuration");
  const int generation = static_cast<int>(r.U32());
  const uint64_t n_candidates = r.U64();
  if (n_candidates > static_cast<uint64_t>(c.population))
    return absl::DataLossError("GA state: more candidates than the population");
  std::vector<Candidate> candidates(n_candidates);
  for (auto& cand : candidates) {
    cand.member = static_cast<int>(r.U32());
    cand.genes = r.F64s();
    if (r.U32() != 0) cand.known = ReadEvaluation(r);
    cand.origin_generation = static_cast<int>(r.U32());
    cand.origin_member = static_cast<int>(r.U32());
  }
  std::vector<Ranked> hof;
  if (!ReadRanked(r, hof, c.population, c.bounds.size()) && r.ok())
    return absl::DataLossError("GA state: malformed hall of fame (larger than the population, "
                               "or genes of another length)");
  if (auto s = r.status("GA state"); !s.ok()) return s;
  for (size_t m = 0; m < candidates.size(); ++m) {
    if (candidates[m].member != static_cast<int>(m) ||
        candidates[m].genes.size() != c.bounds.size())
      return absl::DataLossError("GA state: malformed population");
  }
  if (generation < c.generations && !ReachedStopFitness(hof) &&
      candidates.size() != static_cast<size_t>(c.population))
    return absl::DataLossError("GA state: population size does not match");
  generation_ = generation;
  candidates_ = std::move(candidates);
  hof_ = std::move(hof);
  return absl::OkStatus();
}

}  // namespace gaitforge::engines::ga
