#include "workers/objectives/analytic.h"

#include <gtest/gtest.h>

#include <cmath>

namespace gaitforge::objectives {
namespace {

TEST(Analytic, KnownOptimaAndValues) {
  EXPECT_EQ(Sphere({0, 0, 0}), 0);
  EXPECT_EQ(Rastrigin({0, 0}), 0);
  EXPECT_EQ(Rosenbrock({1, 1, 1}), 0);
  EXPECT_EQ(Ellipsoid({0, 0}), 0);
  EXPECT_DOUBLE_EQ(Sphere({1, 2}), 5);
  EXPECT_DOUBLE_EQ(Ellipsoid({1, 1}), 1 + 1e6);
  EXPECT_NEAR(Rastrigin({1, 0}), 1, 1e-12);
}

TEST(Analytic, OptimumOfTheShiftedObjectiveIsWhereTheDocsSay) {
  auto reg = DefaultRegistry();
  const Objective* o = reg.Find("analytic.sphere");
  ASSERT_NE(o, nullptr);
  EvalInput in;
  in.lo = {0, 0, 0.2};
  in.hi = {1, 1, 2.0};
  in.params = {{"shift", 0.2}};
  // z_i = 10 u - 5 - s_i with s = (+1, -1, +1) * 1  =>  u = (0.6, 0.4, 0.6)
  in.genes = {0.6, 0.4, 0.2 + 0.6 * 1.8};
  const EvalResult r = EvaluateSafely(*o, in);
  ASSERT_TRUE(r.valid);
  EXPECT_NEAR(r.fitness, 0.0, 1e-20);
  in.genes = {0.5, 0.5, 1.1};
  EXPECT_NEAR(EvaluateSafely(*o, in).fitness, -3.0, 1e-12);
}

class Throws final : public Objective {
 public:
  EvalResult Evaluate(const EvalInput&) const override { throw std::runtime_error("boom"); }
};
class NotFinite final : public Objective {
 public:
  EvalResult Evaluate(const EvalInput&) const override {
    return EvalResult{true, NAN, "", {{"m", INFINITY}, {"ok", 1}}};
  }
};

TEST(EvaluateSafely, TurnsFailuresIntoInvalidResultsWithAReason) {
  const EvalResult a = EvaluateSafely(Throws(), {});
  EXPECT_FALSE(a.valid);
  EXPECT_NE(a.reason.find("boom"), std::string::npos);
  const EvalResult b = EvaluateSafely(NotFinite(), {});
  EXPECT_FALSE(b.valid);
  EXPECT_EQ(b.reason, "non-finite fitness");
  EXPECT_EQ(b.metrics.count("m"), 0u);
  EXPECT_EQ(b.metrics.count("ok"), 1u);
}

}  // namespace
}  // namespace gaitforge::objectives
