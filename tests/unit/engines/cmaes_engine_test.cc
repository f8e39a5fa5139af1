#include "services/engines/cmaes/cmaes_engine.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "bench/cmaes_functions.h"

namespace gaitforge::engines::cmaes {
namespace {

using Objective = std::function<double(const std::vector<double>&)>;

// The benchmark's setup (bench/cmaes_bench.cc): x0 uniform in [-5, 5)^d, sigma0 = 2, in a
// box [-100, 100]^d that the search never reaches, IPOP restarts.
CmaesConfig BenchConfig(uint64_t seed, int d) {
  CmaesConfig c;
  c.seed = seed;
  c.bounds.lo.assign(d, -100.0);
  c.bounds.hi.assign(d, 100.0);
  c.mean0 = bench::StartPoint(seed, d);
  c.sigma0_fraction = 2.0 / 200.0;
  c.restarts = Restarts::kIpop;
  c.max_evaluations = 100000;
  return c;
}

// Runs to f < target (fitness = -f) or Done(); returns the evaluations used, or -1.
int64_t EvaluationsToTarget(CmaesEngine& e, const Objective& f, double target = 1e-8) {
  std::vector<Evaluation> evals;
  while (!e.Done()) {
    const auto& cands = e.Ask();
    evals.assign(cands.size(), {});
    double best = INFINITY;
    for (size_t m = 0; m < cands.size(); ++m) {
      const double v = f(cands[m].genes);
      best = std::min(best, v);
      evals[m] = {true, -v, ""};
    }
    EXPECT_TRUE(e.Tell(evals).ok());
    if (best < target) return e.evaluations();
  }
  return -1;
}

void Step(CmaesEngine& e, const Objective& f) {
  std::vector<Evaluation> evals;
  for (const auto& c : e.Ask()) evals.push_back({true, -f(c.genes), ""});
  ASSERT_TRUE(e.Tell(evals).ok());
}

std::unique_ptr<CmaesEngine> Make(const CmaesConfig& c) {
  auto e = CmaesEngine::Create(c);
  EXPECT_TRUE(e.ok()) << e.status();
  return std::move(*e);
}

TEST(CmaesConfigTest, ValidationNamesTheField) {
  CmaesConfig c = BenchConfig(1, 3);
  EXPECT_TRUE(ValidateCmaesConfig(c).ok());
  auto bad = [&](auto mutate, const char* field) {
    CmaesConfig b = c;
    mutate(b);
    const absl::Status s = ValidateCmaesConfig(b);
    EXPECT_FALSE(s.ok()) << field;
    EXPECT_NE(s.message().find(field), std::string::npos) << s.message();
  };
  bad([](CmaesConfig& b) { b.population = 2; }, "cmaes.population");
  bad([](CmaesConfig& b) { b.sigma0_fraction = 0; }, "cmaes.sigma0_fraction");
  bad([](CmaesConfig& b) { b.mean0 = {0, 0}; }, "cmaes.mean0");
  bad([](CmaesConfig& b) { b.mean0[1] = 1000; }, "cmaes.mean0[1]");
  bad([](CmaesConfig& b) { b.max_evaluations = 0; }, "cmaes.max_evaluations");
  bad([](CmaesConfig& b) { b.max_restarts = -1; }, "cmaes.max_restarts");
  bad([](CmaesConfig& b) { b.tolfun = -1; }, "cmaes.tolfun");
  bad([](CmaesConfig& b) { b.bounds.hi[2] = -200; }, "bounds[2]");
  EXPECT_EQ(ParseRestarts("bipop"), Restarts::kBipop);
  EXPECT_FALSE(ParseRestarts("pop").has_value());
}

TEST(CmaesConfigTest, DefaultParametersFollowTheTutorial) {
  const StrategyParams p = DefaultStrategyParams(10, 0);
  EXPECT_EQ(p.lambda, 10);  // 4 + floor(3 ln 10), eq. (48)
  EXPECT_EQ(p.mu, 5);
  double pos = 0, neg = 0;
  for (int i = 0; i < p.lambda; ++i) (p.weights[i] > 0 ? pos : neg) += p.weights[i];
  EXPECT_NEAR(pos, 1.0, 1e-12);  // eq. (53)
  EXPECT_LT(neg, 0.0);
  EXPECT_NEAR(p.mu_eff, 3.1672, 1e-3);
  EXPECT_NEAR(p.c_sigma, (p.mu_eff + 2) / (10 + p.mu_eff + 3), 1e-15);  // Hansen 2001
  // Active update at Hansen & Ros (2010)'s rate, inside the tutorial's bound (eq. 50).
  const double c_neg = (1 - p.c_mu) * p.mu_eff / 4 / (std::pow(12.0, 1.5) + 2 * p.mu_eff);
  EXPECT_NEAR(-neg * p.c_mu, c_neg, 1e-12);
  EXPECT_LT(-neg, 1 + p.c1 / p.c_mu);
  EXPECT_NEAR(p.c1, 2.0 / (11.3 * 11.3 + p.mu_eff), 1e-15);
  EXPECT_LE(p.c1 + p.c_mu, 1.0);
}

TEST(MirrorTest, FoldsIntoTheUnitInterval) {
  EXPECT_EQ(Mirror01(0.25), 0.25);
  EXPECT_DOUBLE_EQ(Mirror01(1.25), 0.75);
  EXPECT_DOUBLE_EQ(Mirror01(-0.25), 0.25);
  EXPECT_DOUBLE_EQ(Mirror01(2.25), 0.25);
  EXPECT_DOUBLE_EQ(Mirror01(-1.75), 0.25);
}

// Evaluation counts to f < 1e-8, median of 5 seeds. Reference: DEAP's CMA-ES medians
// measured in issue 4 on this setup (d = 10: sphere 1464, ellipsoid 5862, Rosenbrock
// 5889), which match the counts reported for the standard (mu/mu_w, lambda)-CMA-ES by
// Hansen & Ostermeier (2001) and Hansen et al. (2003); the limit allows 1.5 times those
// for a 5-seed median. d = 13 scales them by n for the sphere (sigma adapts at a rate ~1/n,
// c_sigma in eq. (55)) and by n^2 for ellipsoid and Rosenbrock (learning C takes O(n^2)
// evaluations: c1, c_mu ~ 1/n^2, eqs. (57)-(58)). Measured here (15 seeds, see
// bench/cmaes_bench.cc): 1470 / 4240 / 5200 in d = 10 and 1947 / 6380 / 8272 in d = 13.
struct ConvergenceCase {
  const char* function;
  int dim;
  double max_median_evals;
};

class CmaesConvergenceTest : public testing::TestWithParam<ConvergenceCase> {};

TEST_P(CmaesConvergenceTest, ReachesTargetWithinKnownEvaluations) {
  const auto& p = GetParam();
  const auto f = bench::FunctionByName(p.function);
  std::vector<double> used;
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    auto e = Make(BenchConfig(seed, p.dim));
    const int64_t n = EvaluationsToTarget(*e, f);
    EXPECT_GT(n, 0) << p.function << " seed " << seed << " stopped: " << e->stop_reason();
    used.push_back(n > 0 ? n : 1e9);
  }
  std::sort(used.begin(), used.end());
  EXPECT_LE(used[2], p.max_median_evals) << p.function << " d = " << p.dim;
}

INSTANTIATE_TEST_SUITE_P(
    Unimodal, CmaesConvergenceTest,
    testing::Values(ConvergenceCase{"sphere", 10, 1.5 * 1464},
                    ConvergenceCase{"ellipsoid", 10, 1.5 * 5862},
                    ConvergenceCase{"rosenbrock", 10, 1.5 * 5889},
                    ConvergenceCase{"sphere", 13, 1.5 * 1464 * 1.3},
                    ConvergenceCase{"ellipsoid", 13, 1.5 * 5862 * 1.69},
                    ConvergenceCase{"rosenbrock", 13, 1.5 * 5889 * 1.69}),
    [](const auto& info) {
      return std::string(info.param.function) + std::to_string(info.param.dim);
    });

// Rastrigin, d = 10, box [-5.12, 5.12]^d, default lambda: a single CMA-ES run ends in a
// local optimum (DEAP: 0 of 15), while restarts with growing populations find the global
// one (Auger & Hansen 2005 report success for lambda of a few hundred in d = 10).
// Required: at least 4 of 5 seeds within 1e6 evaluations (the benchmark solves 15/15).
void RastriginWithRestarts(Restarts restarts) {
  int solved = 0;
  for (uint64_t seed = 1; seed <= 5; ++seed) {
    CmaesConfig c = BenchConfig(seed, 10);
    c.bounds.lo.assign(10, -5.12);
    c.bounds.hi.assign(10, 5.12);
    c.sigma0_fraction = 2.0 / 10.24;
    c.restarts = restarts;
    c.max_evaluations = 1000000;
    auto e = Make(c);
    if (EvaluationsToTarget(*e, bench::Rastrigin) > 0) {
      ++solved;
      EXPECT_GT(e->runs(), 1);  // the default population alone does not get there
    }
  }
  EXPECT_GE(solved, 4);
}

TEST(CmaesRestartTest, IpopSolvesRastrigin) { RastriginWithRestarts(Restarts::kIpop); }
TEST(CmaesRestartTest, BipopSolvesRastrigin) { RastriginWithRestarts(Restarts::kBipop); }

TEST(CmaesRestartTest, IpopDoublesThePopulationAndWithoutRestartsItIsDone) {
  CmaesConfig c = BenchConfig(3, 4);
  c.bounds.lo.assign(4, -5.12);
  c.bounds.hi.assign(4, 5.12);
  c.tolfun = 1e-6;
  c.max_restarts = 2;
  auto e = Make(c);
  std::vector<size_t> sizes;
  while (!e->Done()) {
    if (sizes.empty() || sizes.back() != e->Ask().size()) sizes.push_back(e->Ask().size());
    Step(*e, bench::Rastrigin);
  }
  EXPECT_EQ(sizes, (std::vector<size_t>{8, 16, 32}));
  EXPECT_EQ(e->runs(), 3);
  EXPECT_TRUE(e->Ask().empty());
  c.restarts = Restarts::kNone;
  auto once = Make(c);
  while (!once->Done()) Step(*once, bench::Rastrigin);
  EXPECT_EQ(once->runs(), 1);
  EXPECT_EQ(once->stop_reason(), "tolfun");
}

}  // namespace
}  // namespace gaitforge::engines::cmaes
