#include "services/engines/sweep/sweep_engine.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "services/core/byte_codec.h"

namespace gaitforge::engines::sweep {

SweepEngine::SweepEngine(const SweepConfig& config)
    : config_(config),
      points_(PointsPerGene(config)),
      grid_size_(GridSize(config)),
      grid_best_(config.top_k),
      hof_(10, config.bounds) {}

absl::StatusOr<std::unique_ptr<SweepEngine>> SweepEngine::Create(const SweepConfig& config) {
  if (auto s = ValidateSweepConfig(config); !s.ok()) return s;
  std::unique_ptr<SweepEngine> e(new SweepEngine(config));
  e->BuildCandidates();
  return e;
}

std::vector<double> SweepEngine::GridPoint(int64_t index) const {
  const size_t n = points_.size();
  std::vector<double> x(n);
  std::vector<bool> factored(n, false);
  for (const Factor& f : config_.factors)
    for (int g : f.genes) factored[g] = true;
  for (size_t k = n; k-- > 0;) {
    if (factored[k]) continue;
    const double lo = config_.bounds.lo[k], hi = config_.bounds.hi[k];
    const int p = points_[k];
    const int64_t j = index % p;
    index /= p;
    if (config_.bounds.IsCircular(k))  // lo and hi are one point: p points, hi left out
      x[k] = lo + (hi - lo) * j / p;
    else
      x[k] = p == 1 ? 0.5 * (lo + hi) : (j == p - 1 ? hi : lo + (hi - lo) * j / (p - 1));
  }
  for (size_t f = config_.factors.size(); f-- > 0;) {  // the first factor varies slowest
    const Factor& factor = config_.factors[f];
    const int64_t levels = static_cast<int64_t>(factor.levels.size());
    const std::vector<double>& level = factor.levels[index % levels];
    index /= levels;
    for (size_t k = 0; k < factor.genes.size(); ++k) x[factor.genes[k]] = level[k];
  }
  return x;
}

void SweepEngine::BuildCandidates() {
  candidates_.clear();
  if (in_grid()) {
    const int64_t batch = config_.grid_batch > 0 ? config_.grid_batch : grid_size_;
    const int64_t count = std::min(batch, grid_size_ - grid_next_);
    for (int64_t k = 0; k < count; ++k) {
      const int m = static_cast<int>(k);
      candidates_.push_back(Candidate{m, GridPoint(grid_next_ + k), std::nullopt, generation_, m});
    }
  } else {
    for (const NelderMead& s : searches_) {
      for (const auto& p : s.pending()) {
        const int m = static_cast<int>(candidates_.size());
        candidates_.push_back(Candidate{m, p, std::nullopt, generation_, m});
      }
    }
  }
  const bool over_budget = config_.max_evaluations > 0 &&
                           evaluations_ + static_cast<int64_t>(candidates_.size()) >
                               config_.max_evaluations;
  if (candidates_.empty() || over_budget) {
    done_ = true;
    over_budget_ = over_budget;
    candidates_.clear();
  }
}

std::string SweepEngine::StopReason() const {
  if (!done_) return "";
  if (over_budget_)
    return absl::StrCat("sweep: the next batch would pass max_evaluations = ",
                        config_.max_evaluations, " (", evaluations_, " done)");
  if (config_.top_k == 0) return "sweep: the grid is done (top_k 0: no local searches)";
  return absl::StrCat("sweep: the grid is done and every Nelder-Mead search has converged "
                      "(nm_tolerance) or used nm_max_iterations");
}

void SweepEngine::StartSearches() {
  const size_t n = points_.size();
  std::vector<double> steps(n);
  for (size_t i = 0; i < n; ++i) {
    const double range = config_.bounds.hi[i] - config_.bounds.lo[i];
    const double fraction = config_.nm_initial_step > 0 ? config_.nm_initial_step
                            : points_[i] > 1        ? 1.0 / (points_[i] - 1)
                                                    : 0.1;
    steps[i] = fraction * range;
  }
  for (const Ranked& r : grid_best_.entries())
    searches_.emplace_back(r.genes, r.eval, steps, config_.bounds);
}

absl::Status SweepEngine::Tell(const std::vector<Evaluation>& evals) {
  if (done_) return absl::FailedPreconditionError("sweep: Tell after the sweep ended");
  if (evals.size() != candidates_.size())
    return absl::InvalidArgumentError(absl::StrCat(
        "sweep: Tell got ", evals.size(), " evaluations, expected ", candidates_.size()));
  for (size_t m = 0; m < evals.size(); ++m) {
    if (evals[m].valid && !std::isfinite(evals[m].fitness))
      return absl::InvalidArgumentError(
          absl::StrCat("sweep: member ", m, " is valid with non-finite fitness"));
    if (evals[m].valid && !(evals[m].violation >= 0.0 && std::isfinite(evals[m].violation)))
      return absl::InvalidArgumentError(
          absl::StrCat("sweep: member ", m, " has a violation outside [0, inf)"));
  }
  for (size_t m = 0; m < evals.size(); ++m) {
    const int member = static_cast<int>(m);
    hof_.Offer(generation_, member, candidates_[m].genes, evals[m]);
    if (in_grid()) grid_best_.Offer(generation_, member, candidates_[m].genes, evals[m]);
  }
  evaluations_ += static_cast<int64_t>(evals.size());
  if (in_grid()) {
    grid_next_ += static_cast<int64_t>(evals.size());
    if (!in_grid()) StartSearches();
  } else {
    size_t first = 0;
    for (NelderMead& s : searches_) {
      const size_t count = s.pending().size();
      if (count == 0) continue;
      const std::vector<Evaluation> mine(evals.begin() + first, evals.begin() + first + count);
      first += count;
      s.Tell(mine, config_.bounds, config_.nm_max_iterations, config_.nm_tolerance);
    }
  }
  ++generation_;
  BuildCandidates();
  return absl::OkStatus();
}

namespace {
constexpr uint32_t kStateMagic = 0x31505753;  // "SWP1"

void WriteConfig(core::ByteWriter& w, const SweepConfig& c) {
  w.U64(c.seed);
  w.F64s(c.bounds.lo);
  w.F64s(c.bounds.hi);
  w.F64s(std::vector<double>(c.points_per_axis.begin(), c.points_per_axis.end()));
  w.U32(c.top_k);
  w.U32(c.nm_max_iterations);
  w.F64(c.nm_tolerance);
  w.F64(c.nm_initial_step);
  w.U32(c.grid_batch);
  w.I64(c.max_evaluations);
  if (c.factors.empty()) return;  // a plain grid's state as before factors existed
  w.U32(static_cast<uint32_t>(c.factors.size()));
  for (const Factor& f : c.factors) {
    w.F64s(std::vector<double>(f.genes.begin(), f.genes.end()));
    w.U32(static_cast<uint32_t>(f.levels.size()));
    for (const auto& level : f.levels) w.F64s(level);
  }
}
}  // namespace

std::string SweepEngine::SaveState() const {
  core::ByteWriter w;
  w.U32(kStateMagic);
  WriteConfig(w, config_);
  w.U32(generation_);
  w.I64(evaluations_);
  w.U32(done_ ? 1 : 0);
  w.I64(grid_next_);
  WriteRanked(w, grid_best_.entries());
  w.U64(searches_.size());
  for (const auto& s : searches_) s.Save(w);
  WriteRanked(w, hof_.entries());
  return w.data();
}

absl::Status SweepEngine::LoadState(std::string_view state) {
  core::ByteReader r(state);
  if (r.U32() != kStateMagic) return absl::DataLossError("sweep state: wrong magic number");
  core::ByteWriter mine;
  WriteConfig(mine, config_);
  if (state.substr(4, mine.data().size()) != mine.data())
    return absl::FailedPreconditionError("sweep state belongs to a different configuration");
  core::ByteReader rest(state.substr(4 + mine.data().size()));
  const int generation = static_cast<int>(rest.U32());
  const int64_t evaluations = rest.I64();
  const bool done = rest.U32() != 0;
  const int64_t grid_next = rest.I64();
  const size_t n = points_.size();
  std::vector<Ranked> grid_best, hof;
  bool ok = ReadRanked(rest, grid_best, config_.top_k, n);
  const uint64_t n_searches = rest.U64();
  ok = ok && n_searches <= static_cast<uint64_t>(config_.top_k);
  std::vector<NelderMead> searches;
  for (uint64_t k = 0; ok && k < n_searches; ++k) {
    auto s = NelderMead::Load(rest, n);
    ok = s.has_value();
    if (ok) searches.push_back(std::move(*s));
  }
  ok = ok && ReadRanked(rest, hof, 10, n) && rest.AtEnd();
  ok = ok && grid_next >= 0 && grid_next <= grid_size_;
  if (!ok) return absl::DataLossError("sweep state: malformed or truncated");
  generation_ = generation;
  evaluations_ = evaluations;
  grid_next_ = grid_next;
  grid_best_.set_entries(std::move(grid_best));
  searches_ = std::move(searches);
  hof_.set_entries(std::move(hof));
  done_ = false;
  over_budget_ = false;
  BuildCandidates();  // a pure function of the state above
  done_ = done_ || done;
  if (done_) candidates_.clear();
  return absl::OkStatus();
}

}  // namespace gaitforge::engines::sweep
