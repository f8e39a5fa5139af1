#pragma once
// Grid sweep + Nelder-Mead (the foldable-robot paper's "global parameter sweep, then
// local search seeded in the promising regions"), in batch ask/tell form:
//  1. the grid of sweep_config.h, grid_batch points per generation (default: all at once);
//  2. top_k Nelder-Mead searches (nelder_mead.h) started at the best grid points by
//     RanksBefore (earlier grid points win ties), over all genes; every generation holds
//     the pending points of every unfinished search (the initial simplices, reflections,
//     expansions/contractions and shrinks of different searches share batches).
// Done() when every search has ended or the next batch would exceed max_evaluations.
// Deterministic: no random numbers. Member order in a Nelder-Mead generation: searches in
// order of their seed's rank, each search's pending points in its own order.
#include <memory>

#include "services/engines/hall_of_fame.h"
#include "services/engines/sweep/nelder_mead.h"
#include "services/engines/sweep/sweep_config.h"

namespace gaitforge::engines::sweep {

class SweepEngine final : public Engine {
 public:
  SweepEngine(const SweepEngine&) = delete;
  SweepEngine& operator=(const SweepEngine&) = delete;

  static absl::StatusOr<std::unique_ptr<SweepEngine>> Create(const SweepConfig& config);

  int generation() const override { return generation_; }
  bool Done() const override { return done_; }
  std::string StopReason() const override;
  const std::vector<Candidate>& Ask() const override { return candidates_; }
  absl::Status Tell(const std::vector<Evaluation>& by_member) override;
  std::vector<Ranked> HallOfFame() const override { return hof_.entries(); }
  std::string SaveState() const override;
  absl::Status LoadState(std::string_view state) override;

  int64_t evaluations() const { return evaluations_; }
  bool in_grid() const { return grid_next_ < grid_size_; }
  const std::vector<NelderMead>& searches() const { return searches_; }
  // Genes of grid point `index` (last gene fastest). Exposed for tests.
  std::vector<double> GridPoint(int64_t index) const;

 private:
  explicit SweepEngine(const SweepConfig& config);
  void StartSearches();
  void BuildCandidates();  // from the grid cursor or the searches' pending points

  SweepConfig config_;
  std::vector<int> points_;  // per gene
  int64_t grid_size_ = 0;
  int generation_ = 0;
  int64_t evaluations_ = 0;
  bool done_ = false;
  bool over_budget_ = false;  // done because the next batch would pass max_evaluations
  int64_t grid_next_ = 0;           // first grid point not yet asked
  engines::HallOfFame grid_best_;   // the top_k grid points so far
  std::vector<NelderMead> searches_;
  std::vector<Candidate> candidates_;
  engines::HallOfFame hof_;
};

}  // namespace gaitforge::engines::sweep
