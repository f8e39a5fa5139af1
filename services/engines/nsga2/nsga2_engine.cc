#include "services/engines/nsga2/nsga2_engine.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "absl/strings/str_cat.h"
#include "services/core/byte_codec.h"
#include "services/core/keyed_rng.h"
#include "services/engines/nsga2/nsga2_operators.h"
#include "services/engines/nsga2/pareto.h"

namespace gaitforge::engines::nsga2 {

using core::KeyedRng;
using core::Purpose;

absl::Status ValidateNsga2Config(const Nsga2Config& c) {
  const auto range = [](const char* field, double v, double lo, double hi) {
    return absl::InvalidArgumentError(
        absl::StrCat(field, " = ", v, " is out of range [", lo, ", ", hi, "]"));
  };
  if (c.population < 4 || c.population > kMaxPopulation)
    return range("population", c.population, 4, kMaxPopulation);
  if (c.generations < 1 || c.generations > 100000)
    return range("generations", c.generations, 1, 100000);
  if (c.objectives < 2 || c.objectives > 8)
    return range("nsga2.objectives (count)", c.objectives, 2, 8);
  if (!(c.crossover_rate >= 0 && c.crossover_rate <= 1))
    return range("nsga2.crossover_rate", c.crossover_rate, 0, 1);
  if (!(c.mutation_rate >= 0 && c.mutation_rate <= 1))
    return range("nsga2.mutation_rate", c.mutation_rate, 0, 1);
  if (!(c.crossover_eta >= 0 && c.crossover_eta <= 1000))
    return range("nsga2.crossover_eta", c.crossover_eta, 0, 1000);
  if (!(c.mutation_eta >= 0 && c.mutation_eta <= 1000))
    return range("nsga2.mutation_eta", c.mutation_eta, 0, 1000);
  return ValidateBounds(c.bounds);
}

Nsga2Engine::Nsga2Engine(const Nsga2Config& config) : config_(config) {
  if (config_.mutation_rate <= 0) config_.mutation_rate = 1.0 / config_.bounds.size();
}

absl::StatusOr<std::unique_ptr<Nsga2Engine>> Nsga2Engine::Create(const Nsga2Config& config) {
  if (auto s = ValidateNsga2Config(config); !s.ok()) return s;
  std::unique_ptr<Nsga2Engine> engine(new Nsga2Engine(config));
  engine->InitialPopulation();
  return engine;
}

void Nsga2Engine::InitialPopulation() {
  candidates_.assign(config_.population, Candidate{});
  for (int m = 0; m < config_.population; ++m) {
    KeyedRng rng(config_.seed, 0, m, Purpose::kInit);
    Candidate& c = candidates_[m];
    c.member = c.origin_member = m;
    c.genes.resize(config_.bounds.size());
    for (size_t i = 0; i < c.genes.size(); ++i)
      c.genes[i] = rng.Uniform(config_.bounds.lo[i], config_.bounds.hi[i]);
  }
}

absl::Status Nsga2Engine::CheckTold(const std::vector<Evaluation>& evals) const {
  if (Done()) return absl::FailedPreconditionError("NSGA-II: Tell after the last generation");
  if (evals.size() != candidates_.size())
    return absl::InvalidArgumentError(absl::StrCat("NSGA-II: Tell got ", evals.size(),
                                                   " evaluations, expected ", candidates_.size()));
  for (size_t m = 0; m < evals.size(); ++m) {
    if (!evals[m].valid) continue;
    if (evals[m].objectives.size() != static_cast<size_t>(config_.objectives))
      return absl::InvalidArgumentError(absl::StrCat("NSGA-II: member ", m, " is valid with ",
                                                     evals[m].objectives.size(),
                                                     " objectives, expected ", config_.objectives));
    for (double v : evals[m].objectives)
      if (!std::isfinite(v))
        return absl::InvalidArgumentError(
            absl::StrCat("NSGA-II: member ", m, " is valid with a non-finite objective"));
  }
  return absl::OkStatus();
}

absl::Status Nsga2Engine::Tell(const std::vector<Evaluation>& evals) {
  if (auto s = CheckTold(evals); !s.ok()) return s;
  std::vector<Ranked> pool = parents_;  // parents first: they win ties
  for (size_t m = 0; m < candidates_.size(); ++m) {
    const Candidate& c = candidates_[m];
    pool.push_back(Ranked{generation_, c.member, c.genes, evals[m]});
  }
  SelectParents(std::move(pool));
  ++generation_;
  candidates_.clear();
  if (!Done()) Breed();
  return absl::OkStatus();
}

void Nsga2Engine::SelectParents(std::vector<Ranked> pool) {
  std::vector<Evaluation> evals;
  for (const Ranked& r : pool) evals.push_back(r.eval);
  const auto fronts = NondominatedFronts(evals);
  std::vector<Ranked> parents;
  std::vector<int> front_of;
  std::vector<double> crowding;
  for (size_t f = 0; f < fronts.size() && static_cast<int>(parents.size()) < config_.population;
       ++f) {
    const std::vector<double> d = CrowdingDistances(evals, fronts[f]);
    std::vector<size_t> order(fronts[f].size());
    std::iota(order.begin(), order.end(), 0);
    // Larger crowding distance first; equal ones keep index order (parents before offspring).
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return d[a] > d[b]; });
    for (size_t j : order) {
      if (static_cast<int>(parents.size()) == config_.population) break;
      parents.push_back(pool[fronts[f][j]]);
      front_of.push_back(static_cast<int>(f));
      crowding.push_back(d[j]);
    }
  }
  parents_ = std::move(parents);
  parent_front_ = std::move(front_of);
  parent_crowding_ = std::move(crowding);
  hof_.clear();
  for (size_t p = 0; p < parents_.size() && parent_front_[p] == 0; ++p) {
    bool copy = false;
    for (const Ranked& h : hof_)
      copy = copy || SameGenotype(parents_[p].genes, h.genes, config_.bounds);
    if (!copy) hof_.push_back(parents_[p]);
  }
  std::stable_sort(hof_.begin(), hof_.end(), [](const Ranked& a, const Ranked& b) {
    if (a.eval.valid != b.eval.valid) return a.eval.valid;
    return a.eval.valid && a.eval.objectives[0] > b.eval.objectives[0];
  });
}

void Nsga2Engine::Breed() {
  const int g = generation_;               // the generation being created
  const auto better = [&](int a, int b) {  // the crowded-comparison operator
    if (parent_front_[a] != parent_front_[b]) return parent_front_[a] < parent_front_[b];
    return parent_crowding_[a] > parent_crowding_[b];
  };
  const int n = static_cast<int>(parents_.size());
  candidates_.assign(config_.population, Candidate{});
  for (int first = 0; first < config_.population; first += 2) {
    KeyedRng select(config_.seed, g, first, Purpose::kSelect);
    const auto pick = [&] {
      const int a = static_cast<int>(select.UniformInt(0, n - 1));
      const int b = static_cast<int>(select.UniformInt(0, n - 1));
      return better(b, a) ? b : a;
    };
    std::vector<double> a = parents_[pick()].genes;
    std::vector<double> b = parents_[pick()].genes;
    KeyedRng cross(config_.seed, g, first, Purpose::kCrossover);
    SbxCrossover(a, b, config_.bounds, config_.crossover_rate, config_.crossover_eta, cross);
    for (int k = 0; k < 2 && first + k < config_.population; ++k) {
      Candidate& c = candidates_[first + k];
      c.member = c.origin_member = first + k;
      c.origin_generation = g;
      c.genes = k == 0 ? a : b;
      KeyedRng mutate(config_.seed, g, c.member, Purpose::kMutate);
      PolynomialMutation(c.genes, config_.bounds, config_.mutation_rate, config_.mutation_eta,
                         mutate);
    }
  }
}

}  // namespace gaitforge::engines::nsga2
