// Nsga2Engine's state: configuration (checked on load), generation, offspring, parents with
// their evaluations, objectives, fronts and crowding distances, and the hall of fame.
#include "services/core/byte_codec.h"
#include "services/engines/nsga2/nsga2_engine.h"

namespace gaitforge::engines::nsga2 {
namespace {

constexpr uint32_t kStateMagic = 0x3147534e;  // "NSG1"

void WriteMembers(core::ByteWriter& w, const std::vector<Ranked>& v) {
  WriteRanked(w, v);
  for (const Ranked& r : v) w.F64s(r.eval.objectives);
}

bool ReadMembers(core::ByteReader& r, std::vector<Ranked>& v, size_t cap, size_t n) {
  if (!ReadRanked(r, v, cap, n)) return false;
  for (Ranked& m : v) m.eval.objectives = r.F64s();
  return r.ok();
}

bool SameConfig(const Nsga2Config& a, const Nsga2Config& b) {
  return a.seed == b.seed && a.population == b.population && a.generations == b.generations &&
         a.objectives == b.objectives && a.crossover_rate == b.crossover_rate &&
         a.crossover_eta == b.crossover_eta && a.mutation_eta == b.mutation_eta &&
         a.mutation_rate == b.mutation_rate && a.bounds.lo == b.bounds.lo &&
         a.bounds.hi == b.bounds.hi && a.bounds.circular == b.bounds.circular;
}

}  // namespace

std::string Nsga2Engine::SaveState() const {
  core::ByteWriter w;
  w.U32(kStateMagic);
  w.U64(config_.seed);
  w.U32(config_.population);
  w.U32(config_.generations);
  w.U32(config_.objectives);
  w.F64s(
      {config_.crossover_rate, config_.crossover_eta, config_.mutation_eta, config_.mutation_rate});
  w.F64s(config_.bounds.lo);
  w.F64s(config_.bounds.hi);
  std::vector<double> circular;
  for (size_t i = 0; i < config_.bounds.size(); ++i)
    circular.push_back(config_.bounds.IsCircular(i));
  w.F64s(circular);
  w.U32(generation_);
  w.U64(candidates_.size());
  for (const Candidate& c : candidates_) w.F64s(c.genes);
  WriteMembers(w, parents_);
  std::vector<double> fronts(parent_front_.begin(), parent_front_.end());
  w.F64s(fronts);
  w.F64s(parent_crowding_);
  WriteMembers(w, hof_);
  return w.data();
}

absl::Status Nsga2Engine::LoadState(std::string_view state) {
  core::ByteReader r(state);
  if (r.U32() != kStateMagic) return absl::DataLossError("NSGA-II state: wrong magic number");
  Nsga2Config c;
  c.seed = r.U64();
  c.population = static_cast<int>(r.U32());
  c.generations = static_cast<int>(r.U32());
  c.objectives = static_cast<int>(r.U32());
  const std::vector<double> rates = r.F64s();
  if (rates.size() == 4) {
    c.crossover_rate = rates[0], c.crossover_eta = rates[1], c.mutation_eta = rates[2];
    c.mutation_rate = rates[3];
  }
  c.bounds.lo = r.F64s();
  c.bounds.hi = r.F64s();
  for (double x : r.F64s()) c.bounds.circular.push_back(x != 0);
  Nsga2Config mine = config_;
  mine.bounds.circular.resize(mine.bounds.size(), false);
  if (!r.ok() || !SameConfig(c, mine))
    return absl::FailedPreconditionError("NSGA-II state belongs to a different configuration");
  const size_t n = c.bounds.size(), cap = static_cast<size_t>(c.population);
  const int generation = static_cast<int>(r.U32());
  const uint64_t n_candidates = r.U64();
  if (n_candidates > cap)
    return absl::DataLossError("NSGA-II state: more offspring than the population");
  std::vector<Candidate> candidates(n_candidates);
  for (size_t m = 0; m < candidates.size(); ++m) {
    candidates[m].member = candidates[m].origin_member = static_cast<int>(m);
    candidates[m].origin_generation = generation;
    candidates[m].genes = r.F64s();
    if (candidates[m].genes.size() != n)
      return absl::DataLossError("NSGA-II state: malformed offspring");
  }
  std::vector<Ranked> parents, hof;
  const bool parents_ok = ReadMembers(r, parents, cap, n);
  const std::vector<double> fronts = parents_ok ? r.F64s() : std::vector<double>();
  const std::vector<double> crowding = parents_ok ? r.F64s() : std::vector<double>();
  const bool hof_ok = parents_ok && ReadMembers(r, hof, cap, n);
  if (auto s = r.status("NSGA-II state"); !s.ok()) return s;
  if (!hof_ok || fronts.size() != parents.size() || crowding.size() != parents.size())
    return absl::DataLossError("NSGA-II state: malformed parents or hall of fame");
  generation_ = generation;
  candidates_ = std::move(candidates);
  parents_ = std::move(parents);
  parent_front_.assign(fronts.begin(), fronts.end());
  parent_crowding_ = crowding;
  hof_ = std::move(hof);
  return absl::OkStatus();
}

}  // namespace gaitforge::engines::nsga2
