#include "services/engines/cmaes/cmaes_engine.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <Eigen/Eigenvalues>

#include "absl/strings/str_cat.h"
#include "services/core/keyed_rng.h"

namespace gaitforge::engines::cmaes {

using core::KeyedRng;
using core::Purpose;

double Mirror01(double u) {
  if (u >= 0.0 && u <= 1.0) return u;
  double t = std::fmod(u, 2.0);  // in (-2, 2)
  if (t < 0.0) t += 2.0;         // in [0, 2)
  if (t > 1.0) t = 2.0 - t;
  return std::clamp(t, 0.0, 1.0);
}

CmaesEngine::CmaesEngine(const CmaesConfig& config)
    : config_(config), n_(static_cast<int>(config.bounds.size())), hof_(10, config.bounds) {}

absl::StatusOr<std::unique_ptr<CmaesEngine>> CmaesEngine::Create(const CmaesConfig& config) {
  if (auto s = ValidateCmaesConfig(config); !s.ok()) return s;
  std::unique_ptr<CmaesEngine> e(new CmaesEngine(config));
  e->base_lambda_ = config.population > 0 ? config.population : DefaultPopulation(e->n_);
  Eigen::VectorXd mean = Eigen::VectorXd::Constant(e->n_, 0.5);
  for (int i = 0; i < e->n_ && !config.mean0.empty(); ++i)
    mean[i] = (config.mean0[i] - config.bounds.lo[i]) / (config.bounds.hi[i] - config.bounds.lo[i]);
  e->StartRun(e->base_lambda_, mean, config.sigma0_fraction, 0);
  if (e->base_lambda_ > config.max_evaluations) {
    e->done_ = true;
    e->stop_reason_ = "max_evaluations";
    e->candidates_.clear();
  }
  return e;
}

void CmaesEngine::StartRun(int lambda, const Eigen::VectorXd& mean, double sigma,
                           int64_t budget) {
  params_ = DefaultStrategyParams(n_, lambda);
  mean_ = mean;
  sigma_ = sigma;
  run_sigma0_ = sigma;
  C_ = Eigen::MatrixXd::Identity(n_, n_);
  B_ = Eigen::MatrixXd::Identity(n_, n_);
  D_ = Eigen::VectorXd::Ones(n_);
  pc_ = Eigen::VectorXd::Zero(n_);
  ps_ = Eigen::VectorXd::Zero(n_);
  run_generation_ = 0;
  eigen_evals_ = 0;
  best_history_.clear();
  run_start_evals_ = evaluations_;
  run_budget_ = budget;
  Sample();
}

// Sampling, eqs. (38)-(40): z_k ~ N(0, I), y_k = B D z_k, x_k = m + sigma y_k; then the
// mirror repair of the header comment and the map from the unit box to the genes.
void CmaesEngine::Sample() {
  const int lambda = params_.lambda;
  Z_.resize(n_, lambda);
  for (int k = 0; k < lambda; ++k) {
    KeyedRng rng(config_.seed, generation_, k, Purpose::kEngine);
    // Marsaglia's polar method: two N(0, 1) values per accepted pair, no trigonometry
    // (this is a third of the engine's cost per generation in d = 10).
    for (int i = 0; i < n_; i += 2) {
      double a, b, s;
      do {
        a = 2.0 * rng.Uniform01() - 1.0;
        b = 2.0 * rng.Uniform01() - 1.0;
        s = a * a + b * b;
      } while (s >= 1.0 || s == 0.0);
      const double scale = std::sqrt(-2.0 * std::log(s) / s);
      Z_(i, k) = a * scale;
      if (i + 1 < n_) Z_(i + 1, k) = b * scale;
    }
  }
  Y_.noalias() = B_ * D_.asDiagonal() * Z_;
  FillCandidates();
}

void CmaesEngine::FillCandidates() {
  const int lambda = params_.lambda;
  candidates_.resize(lambda);
  for (int k = 0; k < lambda; ++k) {
    Candidate& c = candidates_[k];
    c.member = k;
    c.known.reset();
    c.origin_generation = generation_;
    c.origin_member = k;
    c.genes.resize(n_);
    for (int i = 0; i < n_; ++i) {
      const double lo = config_.bounds.lo[i], hi = config_.bounds.hi[i];
      const double x = mean_[i] + sigma_ * Y_(i, k);
      // A circular gene wraps round its cycle (0 and 1 are one point); others reflect.
      const double u = config_.bounds.IsCircular(i) ? x - std::floor(x) : Mirror01(x);
      c.genes[i] = config_.bounds.Fold(i, lo + (hi - lo) * u);
    }
  }
}

absl::Status CmaesEngine::Tell(const std::vector<Evaluation>& evals) {
  if (done_) return absl::FailedPreconditionError("CMA-ES: Tell after the run ended");
  const int lambda = params_.lambda;
  if (static_cast<int>(evals.size()) != lambda)
    return absl::InvalidArgumentError(absl::StrCat("CMA-ES: Tell got ", evals.size(),
                                                   " evaluations, expected ", lambda));
  for (size_t m = 0; m < evals.size(); ++m) {
    if (evals[m].valid && !std::isfinite(evals[m].fitness))
      return absl::InvalidArgumentError(
          absl::StrCat("CMA-ES: member ", m, " is valid with non-finite fitness"));
    if (evals[m].valid && !(evals[m].violation >= 0.0 && std::isfinite(evals[m].violation)))
      return absl::InvalidArgumentError(
          absl::StrCat("CMA-ES: member ", m, " has a violation outside [0, inf)"));
  }
  std::vector<int> order(lambda);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](int a, int b) { return RanksBefore(evals[a], a, evals[b], b); });
  for (int r = 0; r < lambda && hof_.Admits(evals[order[r]]); ++r)
    hof_.Offer(generation_, order[r], candidates_[order[r]].genes, evals[order[r]]);
  evaluations_ += lambda;
  const Evaluation& best = evals[order[0]];
  const bool best_feasible = best.valid && best.violation <= 0.0;
  PushBest(best_feasible ? best.fitness : std::numeric_limits<double>::quiet_NaN());

  Update(order);
  ++generation_;
  ++run_generation_;
  if (config_.stop_fitness && best_feasible && best.fitness >= *config_.stop_fitness) {
    done_ = true;
    stop_reason_ = "stop_fitness";
  } else if (std::string why = RunStopReason(evals, order[0]); !why.empty()) {
    stop_reason_ = why;
    done_ = !Restart();
  } else if (evaluations_ + lambda > config_.max_evaluations) {
    done_ = true;
    stop_reason_ = "max_evaluations";
  } else {
    Sample();
  }
  if (done_) candidates_.clear();
  return absl::OkStatus();
}

std::string CmaesEngine::StopReason() const {
  if (!done_) return "";
  if (stop_reason_ == "stop_fitness")
    return absl::StrCat("CMA-ES reached stop_fitness ", *config_.stop_fitness);
  if (stop_reason_ == "max_evaluations")
    return absl::StrCat("CMA-ES: another generation would pass max_evaluations = ",
                        config_.max_evaluations, " (", evaluations_, " done)");
  return absl::StrCat("CMA-ES: run ", runs(), " stopped on ", stop_reason_,
                      " and no restart is left (restarts, max_restarts or the budget)");
}

void CmaesEngine::PushBest(double f) {
  // Enough history for tolfun: 10 + ceil(30 n / lambda) generations (tutorial, App. B.3).
  const size_t keep = 10 + (30 * n_ + params_.lambda - 1) / params_.lambda;
  if (best_history_.size() >= keep)
    best_history_.erase(best_history_.begin(), best_history_.end() - (keep - 1));
  best_history_.push_back(f);
}

void CmaesEngine::Update(const std::vector<int>& order) {
  const StrategyParams& p = params_;
  const int lambda = p.lambda;
  // eq. (41): <y>_w = sum_{i <= mu} w_i y_{i:lambda}; likewise <z>_w, with C^{-1/2} <y>_w
  // = B <z>_w because y = B D z and C^{-1/2} = B D^{-1} B^T.
  Eigen::VectorXd yw = Eigen::VectorXd::Zero(n_), zw = Eigen::VectorXd::Zero(n_);
  ysel_.resize(n_, lambda);
  wcirc_.resize(lambda);
  for (int r = 0; r < lambda; ++r) {
    const int k = order[r];
    const double w = p.weights[r];
    if (w > 0) {
      yw.noalias() += w * Y_.col(k);
      zw.noalias() += w * Z_.col(k);
    }
    ysel_.col(r) = Y_.col(k);
    // eq. (46): w°_i = w_i for w_i >= 0, else w_i n / ||C^{-1/2} y_{i:lambda}||^2, where
    // ||C^{-1/2} y||^2 = ||z||^2.
    const double z2 = Z_.col(k).squaredNorm();
    wcirc_[r] = w >= 0 ? w : w * n_ / std::max(z2, 1e-300);
  }
  // eq. (42): m <- m + c_m sigma <y>_w.
  mean_.noalias() += p.c_m * sigma_ * yw;
  // eq. (43): p_sigma <- (1 - c_sigma) p_sigma + sqrt(c_sigma (2 - c_sigma) mu_eff) C^{-1/2} <y>_w.
  ps_ = (1.0 - p.c_sigma) * ps_ +
        std::sqrt(p.c_sigma * (2.0 - p.c_sigma) * p.mu_eff) * (B_ * zw);
  const double ps_norm = ps_.norm();
  // h_sigma (below eq. (45)): stall the rank-one update when ||p_sigma|| is large.
  const double ps_bias = std::sqrt(1.0 - std::pow(1.0 - p.c_sigma, 2.0 * (run_generation_ + 1)));
  const bool h_sigma = ps_norm / ps_bias < (1.4 + 2.0 / (n_ + 1.0)) * p.chi_n;
  // eq. (45): p_c <- (1 - c_c) p_c + h_sigma sqrt(c_c (2 - c_c) mu_eff) <y>_w.
  pc_ *= 1.0 - p.c_c;
  if (h_sigma) pc_.noalias() += std::sqrt(p.c_c * (2.0 - p.c_c) * p.mu_eff) * yw;
  // eq. (47): C <- (1 + c1 delta(h) - c1 - c_mu sum w_j) C + c1 p_c p_c^T
  //                 + c_mu sum_i w°_i y_{i:lambda} y_{i:lambda}^T,
  // with delta(h_sigma) = (1 - h_sigma) c_c (2 - c_c).
  const double delta = h_sigma ? 0.0 : p.c_c * (2.0 - p.c_c);
  C_ *= 1.0 + p.c1 * delta - p.c1 - p.c_mu * p.sum_weights;
  C_.noalias() += p.c1 * pc_ * pc_.transpose();
  C_.noalias() += p.c_mu * (ysel_ * wcirc_.asDiagonal()) * ysel_.transpose();
  // eq. (44): sigma <- sigma exp(c_sigma / d_sigma (||p_sigma|| / E||N(0, I)|| - 1)); the
  // exponent is capped at 1 (as pycma does) against a blow-up in the first generations.
  sigma_ *= std::exp(std::min(1.0, p.c_sigma / p.d_sigma * (ps_norm / p.chi_n - 1.0)));
  // Lazy eigendecomposition (tutorial App. B.2 / purecmaes): every
  // lambda / ((c1 + c_mu) n 10) evaluations, which in low dimensions is every generation.
  const int64_t run_evals = evaluations_ - run_start_evals_;
  if (run_evals - eigen_evals_ > lambda / ((p.c1 + p.c_mu) * n_ * 10.0)) {
    eigen_evals_ = run_evals;
    UpdateEigen();
  }
}

void CmaesEngine::UpdateEigen() {
  Eigen::MatrixXd sym = C_.triangularView<Eigen::Lower>();
  sym.triangularView<Eigen::StrictlyUpper>() = C_.transpose().triangularView<Eigen::StrictlyUpper>();
  C_ = sym;  // enforce exact symmetry
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(C_);
  B_ = es.eigenvectors();
  // Non-positive eigenvalues only come from rounding; RunStopReason stops the run then.
  D_ = es.eigenvalues().cwiseMax(0.0).cwiseSqrt();
}

std::string CmaesEngine::RunStopReason(const std::vector<Evaluation>& evals, int best) const {
  const StrategyParams& p = params_;
  if (!std::isfinite(sigma_) || !mean_.allFinite() || !C_.allFinite()) return "numerics";
  const double dmin = D_.minCoeff(), dmax = D_.maxCoeff();
  if (!(dmin > 0.0) || dmax * dmax > config_.max_condition * dmin * dmin) return "condition";
  // tolfun: the recent best values and all current values span less than tolfun.
  const size_t keep = 10 + (30 * n_ + p.lambda - 1) / p.lambda;
  if (best_history_.size() >= keep) {
    double lo = evals[best].fitness, hi = lo;
    bool all = true;
    for (double f : best_history_) {
      all = all && !std::isnan(f);
      lo = std::min(lo, f);
      hi = std::max(hi, f);
    }
    for (const Evaluation& e : evals) {
      all = all && e.valid && e.violation <= 0.0;
      lo = std::min(lo, e.fitness);
      hi = std::max(hi, e.fitness);
    }
    if (all && hi - lo < config_.tolfun) return "tolfun";
  }
  // tolx: sigma sqrt(C_ii) and sigma |p_c,i| below tolx in every coordinate.
  bool small = true;
  for (int i = 0; i < n_ && small; ++i)
    small = sigma_ * std::sqrt(C_(i, i)) < config_.tolx && sigma_ * std::abs(pc_[i]) < config_.tolx;
  if (small) return "tolx";
  // tolxup: the largest axis grew by more than 1e4 times sigma0 (sigma0 far too small).
  if (sigma_ * dmax > 1e4 * run_sigma0_) return "tolxup";
  // No effect of 0.1 sigma along one principal axis, or of 0.2 sigma on any coordinate.
  const int axis = run_generation_ % n_;
  bool no_axis = true;
  for (int i = 0; i < n_ && no_axis; ++i)
    no_axis = mean_[i] == mean_[i] + 0.1 * sigma_ * D_[axis] * B_(i, axis);
  if (no_axis) return "noeffectaxis";
  for (int i = 0; i < n_; ++i)
    if (mean_[i] == mean_[i] + 0.2 * sigma_ * std::sqrt(C_(i, i))) return "noeffectcoord";
  if (run_budget_ > 0 && evaluations_ - run_start_evals_ + p.lambda > run_budget_)
    return "run_budget";
  return "";
}

bool CmaesEngine::Restart() {
  if (config_.restarts == Restarts::kNone) return false;
  const int64_t spent = evaluations_ - run_start_evals_;
  if (small_run_) {
    evals_small_ += spent;
  } else {
    evals_large_ += spent;
    last_large_evals_ = spent;
  }
  KeyedRng rng(config_.seed, generation_, kRestartStream, Purpose::kEngine);
  const double u1 = rng.Uniform01(), u2 = rng.Uniform01();
  Eigen::VectorXd mean(n_);
  for (int i = 0; i < n_; ++i) mean[i] = rng.Uniform01();
  // BIPOP: the first restart doubles; later, the regime that has used fewer evaluations.
  const bool small = config_.restarts == Restarts::kBipop && doublings_ > 0 &&
                     evals_small_ < evals_large_;
  int lambda;
  double sigma = config_.sigma0_fraction;
  int64_t budget = 0;
  if (small) {
    // lambda_s = floor(lambda_def (lambda_l / (2 lambda_def))^(U1^2)),
    // sigma_s = sigma0 10^(-2 U2); budget: half the last large run (Hansen 2009).
    const double lambda_large = static_cast<double>(base_lambda_) * std::ldexp(1.0, doublings_);
    lambda = std::max(4, static_cast<int>(std::floor(
                             base_lambda_ * std::pow(lambda_large / (2.0 * base_lambda_), u1 * u1))));
    sigma *= std::pow(10.0, -2.0 * u2);
    budget = std::max<int64_t>(last_large_evals_ / 2, 2 * lambda);
  } else {
    if (doublings_ >= config_.max_restarts) return false;
    ++doublings_;
    lambda = static_cast<int>(std::min<int64_t>(int64_t{base_lambda_} << doublings_, 1 << 24));
  }
  if (evaluations_ + lambda > config_.max_evaluations) return false;
  small_run_ = small;
  ++run_;
  StartRun(lambda, mean, sigma, budget);
  return true;
}

std::vector<double> CmaesEngine::Spread() const {
  std::vector<double> out;
  if (C_.rows() == 0) return out;
  for (int i = 0; i < C_.rows(); ++i)
    out.push_back(sigma_ * std::sqrt(C_(i, i)) * (config_.bounds.hi[i] - config_.bounds.lo[i]));
  return out;
}

}  // namespace gaitforge::engines::cmaes
