#pragma once
// CMA-ES in ask/tell form after N. Hansen, "The CMA Evolution Strategy: A Tutorial",
// arXiv:1604.00772 (2016): weighted recombination with the tutorial's default (active,
// i.e. also negative) weights, cumulative step-size adaptation, rank-one and rank-mu
// covariance updates. Equation numbers in cmaes_engine.cc and cmaes_config.cc refer to it.
//
// Search space. The engine works on the box normalised to u in [0, 1]^n (gene i is
// lo_i + (hi_i - lo_i) u_i), so sigma0_fraction and tolx are fractions of each range.
//
// Box bounds: periodic mirroring (reflection) of the sampled point. A sample x = m + sigma y
// is folded back into [0, 1] coordinate-wise by reflecting at the faces (u mod 2, then
// 2 - u above 1), so every evaluated candidate lies inside the box; the *unrepaired* sample
// y is what the update uses. The strategy thus optimises the mirror-extended function
// f(mirror(x)), which is continuous, so the search moves freely across a face instead of
// stalling there: an optimum on a face is a (kinked) optimum of the extended function.
// The mean itself may lie outside the box; only evaluated genes are reported.
//
// Ranking: members are sorted by RanksBefore (invalid last, infeasible by violation below
// feasible ones, feasible by fitness): every member gets the weight of its rank (none is
// dropped), so infeasible ones receive the negative weights.
//
// Randomness (all from KeyedRng with Purpose::kEngine): sample k of generation g draws
// its N(0, I) vector z_k from (seed, g, k) (uniform pairs to normals by the polar
// method); a restart decided in Tell() of generation g draws from (seed, g,
// kRestartStream).
//
// Stopping (per run): tolfun, tolx, condition of C > max_condition, tolxup (sigma * max
// axis grew by 1e4), no effect of an axis / coordinate, the run's own budget (BIPOP's
// small runs). When a run stops, restarts (IPOP / BIPOP, cmaes_config.h) begin the next
// run within the same Tell(), so a study keeps them: generation numbers keep counting and
// Ask() simply returns the new lambda candidates. The engine is Done() when the run stops
// and no restart is left, when the next generation would exceed max_evaluations, or when
// stop_fitness is reached.
#include <memory>
#include <string>

#include "services/engines/cmaes/cmaes_config.h"
#include "services/engines/hall_of_fame.h"

namespace gaitforge::engines::cmaes {

class CmaesEngine final : public Engine {
 public:
  static constexpr uint64_t kRestartStream = uint64_t{1} << 40;

  CmaesEngine(const CmaesEngine&) = delete;
  CmaesEngine& operator=(const CmaesEngine&) = delete;

  static absl::StatusOr<std::unique_ptr<CmaesEngine>> Create(const CmaesConfig& config);

  int generation() const override { return generation_; }
  bool Done() const override { return done_; }
  std::string StopReason() const override;
  const std::vector<Candidate>& Ask() const override { return candidates_; }
  absl::Status Tell(const std::vector<Evaluation>& by_member) override;
  std::vector<Ranked> HallOfFame() const override { return hof_.entries(); }
  std::string SaveState() const override;
  absl::Status LoadState(std::string_view state) override;

  // Introspection (tests, benchmarks, status pages).
  int64_t evaluations() const { return evaluations_; }
  int lambda() const { return params_.lambda; }
  int runs() const { return run_ + 1; }      // runs started, the first included
  double sigma() const { return sigma_; }    // in the normalised box
  std::vector<double> Spread() const override;
  const std::string& stop_reason() const { return stop_reason_; }  // last run's

 private:
  explicit CmaesEngine(const CmaesConfig& config);
  void StartRun(int lambda, const Eigen::VectorXd& mean, double sigma, int64_t budget);
  void Sample();          // draws Z, Y for generation_, then FillCandidates()
  void FillCandidates();  // genes of every member from mean, sigma and Y
  void Update(const std::vector<int>& order);
  void UpdateEigen();
  std::string RunStopReason(const std::vector<Evaluation>& evals, int best) const;
  bool Restart();  // false when no restart is left
  void PushBest(double f);

  CmaesConfig config_;
  int n_ = 0;
  int base_lambda_ = 0;  // lambda of the first run (the default or config.population)
  // Study-wide state.
  int generation_ = 0;
  int64_t evaluations_ = 0;
  bool done_ = false;
  std::string stop_reason_;
  int run_ = 0;                // index of the current run
  int doublings_ = 0;          // IPOP / BIPOP large-regime restarts so far
  int64_t evals_large_ = 0;    // BIPOP: evaluations spent in each regime
  int64_t evals_small_ = 0;
  int64_t last_large_evals_ = 0;  // BIPOP: evaluations of the last large run
  bool small_run_ = false;
  int64_t run_start_evals_ = 0;
  int64_t run_budget_ = 0;     // 0: no per-run limit
  // Per-run strategy state (normalised box).
  StrategyParams params_;      // derived from (n, lambda); not serialised
  Eigen::VectorXd mean_;
  double sigma_ = 0;
  double run_sigma0_ = 0;
  Eigen::MatrixXd C_, B_;
  Eigen::VectorXd D_;          // sqrt of C's eigenvalues: C = B diag(D^2) B^T
  Eigen::VectorXd pc_, ps_;
  int run_generation_ = 0;
  int64_t eigen_evals_ = 0;    // run evaluations at the last eigendecomposition
  std::vector<double> best_history_;  // best feasible fitness per generation (NaN: none)
  Eigen::MatrixXd Z_, Y_;      // this generation's z_k ~ N(0, I) and y_k = B D z_k
  std::vector<Candidate> candidates_;
  engines::HallOfFame hof_;
  // Scratch (not state).
  Eigen::MatrixXd ysel_;
  Eigen::VectorXd wcirc_;
};

// Folds u into [0, 1] by reflection at 0 and 1 (period 2). Exposed for tests.
double Mirror01(double u);

}  // namespace gaitforge::engines::cmaes
