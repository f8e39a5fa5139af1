#include "services/engines/cmaes/cmaes_config.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"

namespace gaitforge::engines::cmaes {

std::optional<Restarts> ParseRestarts(std::string_view name) {
  if (name == "none") return Restarts::kNone;
  if (name == "ipop") return Restarts::kIpop;
  if (name == "bipop") return Restarts::kBipop;
  return std::nullopt;
}

std::string_view RestartsName(Restarts r) {
  switch (r) {
    case Restarts::kIpop: return "ipop";
    case Restarts::kBipop: return "bipop";
    case Restarts::kNone: break;
  }
  return "none";
}

absl::Status ValidateCmaesConfig(const CmaesConfig& c) {
  using absl::InvalidArgumentError;
  using absl::StrCat;
  if (auto s = ValidateBounds(c.bounds); !s.ok()) return s;
  if (c.bounds.size() > 1000)
    return InvalidArgumentError(
        StrCat("bounds: ", c.bounds.size(), " genes is out of range [1, 1000] for cmaes"));
  if (!c.mean0.empty()) {
    if (c.mean0.size() != c.bounds.size())
      return InvalidArgumentError(StrCat("cmaes.mean0 has ", c.mean0.size(),
                                         " values, expected one per gene (",
                                         c.bounds.size(), ")"));
    for (size_t i = 0; i < c.mean0.size(); ++i)
      if (!(c.mean0[i] >= c.bounds.lo[i] && c.mean0[i] <= c.bounds.hi[i]))
        return InvalidArgumentError(StrCat("cmaes.mean0[", i, "] = ", c.mean0[i],
                                           " is out of range [", c.bounds.lo[i], ", ",
                                           c.bounds.hi[i], "]"));
  }
  if (!(c.sigma0_fraction > 0.0 && c.sigma0_fraction <= 1.0))
    return InvalidArgumentError(StrCat("cmaes.sigma0_fraction = ", c.sigma0_fraction,
                                       " is out of range (0, 1]"));
  if (c.population != 0 && (c.population < 4 || c.population > 100000))
    return InvalidArgumentError(StrCat("cmaes.population = ", c.population,
                                       " is out of range {0 (default)} or [4, 100000]"));
  if (c.max_evaluations < 1 || c.max_evaluations > int64_t{1} << 40)
    return InvalidArgumentError(StrCat("cmaes.max_evaluations = ", c.max_evaluations,
                                       " is out of range [1, 2^40]"));
  if (c.max_restarts < 0 || c.max_restarts > 20)
    return InvalidArgumentError(
        StrCat("cmaes.max_restarts = ", c.max_restarts, " is out of range [0, 20]"));
  if (!(c.tolfun >= 0.0 && std::isfinite(c.tolfun)))
    return InvalidArgumentError(
        StrCat("cmaes.tolfun = ", c.tolfun, " is out of range [0, inf)"));
  if (!(c.tolx >= 0.0 && std::isfinite(c.tolx)))
    return InvalidArgumentError(StrCat("cmaes.tolx = ", c.tolx, " is out of range [0, inf)"));
  if (!(c.max_condition > 1.0))
    return InvalidArgumentError(
        StrCat("cmaes.max_condition = ", c.max_condition, " is out of range (1, inf]"));
  if (c.stop_fitness && std::isnan(*c.stop_fitness))
    return InvalidArgumentError("cmaes.stop_fitness is NaN");
  return absl::OkStatus();
}

int DefaultPopulation(int n) {
  return 4 + static_cast<int>(std::floor(3.0 * std::log(static_cast<double>(n))));  // (48)
}

StrategyParams DefaultStrategyParams(int n, int lambda) {
  StrategyParams p;
  const double dn = n;
  p.n = n;
  p.lambda = lambda > 0 ? lambda : DefaultPopulation(n);
  p.mu = p.lambda / 2;  // eq. (48): mu = floor(lambda / 2)
  // eq. (49): w'_i = ln((lambda + 1) / 2) - ln i, i = 1..lambda.
  Eigen::VectorXd wp(p.lambda);
  for (int i = 0; i < p.lambda; ++i) wp[i] = std::log((p.lambda + 1) / 2.0) - std::log(i + 1.0);
  double pos_sum = 0, pos_sq = 0, neg_sum = 0, neg_sq = 0;
  for (int i = 0; i < p.lambda; ++i) {
    if (wp[i] > 0) {
      pos_sum += wp[i];
      pos_sq += wp[i] * wp[i];
    } else {
      neg_sum += wp[i];
      neg_sq += wp[i] * wp[i];
    }
  }
  p.mu_eff = pos_sum * pos_sum / pos_sq;  // definition below eq. (49)
  const double mu_eff_neg = neg_sq > 0 ? neg_sum * neg_sum / neg_sq : 0.0;
  // c_sigma as in Hansen & Ostermeier (2001), eq. (16), and pycma's default: (mu_eff + 2) /
  // (n + mu_eff + 3). The 2016 tutorial's eq. (55) has + 5 in the denominator; + 3 adapts the
  // step size a little faster: fewer evaluations on the sphere (bench/engines.py).
  p.c_sigma = (p.mu_eff + 2.0) / (dn + p.mu_eff + 3.0);
  // d_sigma: eq. (55).
  p.d_sigma =
      1.0 + 2.0 * std::max(0.0, std::sqrt((p.mu_eff - 1.0) / (dn + 1.0)) - 1.0) + p.c_sigma;
  // eq. (56)
  p.c_c = (4.0 + p.mu_eff / dn) / (dn + 4.0 + 2.0 * p.mu_eff / dn);
  // eq. (57), alpha_cov = 2
  const double alpha_cov = 2.0;
  p.c1 = alpha_cov / ((dn + 1.3) * (dn + 1.3) + p.mu_eff);
  // eq. (58)
  p.c_mu = std::min(1.0 - p.c1, alpha_cov * (p.mu_eff - 2.0 + 1.0 / p.mu_eff) /
                                    ((dn + 2.0) * (dn + 2.0) + alpha_cov * p.mu_eff / 2.0));
  // eqs. (50)-(52): the scale of the negative weights.
  const double alpha_mu_neg = 1.0 + p.c1 / p.c_mu;
  const double alpha_mueff_neg = 1.0 + 2.0 * mu_eff_neg / (p.mu_eff + 2.0);
  const double alpha_posdef_neg = (1.0 - p.c1 - p.c_mu) / (dn * p.c_mu);
  // The rate of the negative (active) update, c_mu * neg_scale, follows Hansen & Ros (2010),
  // "Benchmarking a weighted negative covariance matrix update on the BBOB-2010 noiseless
  // testbed": c^- = (1 - c_mu) mu_eff / 4 / ((n + 2)^1.5 + 2 mu_eff), bounded by the
  // tutorial's eqs. (50)-(52). (The tutorial's bound alone, about twice that rate at n = 10,
  // measured 3-6% more evaluations on the sphere for 0-2% fewer on Rosenbrock.)
  const double c_neg = (1.0 - p.c_mu) * p.mu_eff / 4.0 / (std::pow(dn + 2.0, 1.5) + 2.0 * p.mu_eff);
  double neg_scale = std::min({alpha_mu_neg, alpha_mueff_neg, alpha_posdef_neg, c_neg / p.c_mu});
  // eq. (53): positive weights sum to one, negative ones to -neg_scale.
  p.weights.resize(p.lambda);
  for (int i = 0; i < p.lambda; ++i)
    p.weights[i] = wp[i] >= 0 ? wp[i] / pos_sum : neg_scale * wp[i] / -neg_sum;
  p.sum_weights = p.weights.sum();
  p.c_m = 1.0;  // eq. (54)
  // E||N(0, I)|| ~ sqrt(n) (1 - 1/(4n) + 1/(21 n^2)) (tutorial, below eq. (44)).
  p.chi_n = std::sqrt(dn) * (1.0 - 1.0 / (4.0 * dn) + 1.0 / (21.0 * dn * dn));
  return p;
}

}  // namespace gaitforge::engines::cmaes
