// NSGA-II (services/engines/nsga2): constrained domination, fronts and crowding on hand-
// worked sets, the variation operators' ranges and streams, the front it finds on ZDT1
// (Zitzler, Deb, Thiele 2000; its true front is f2 = 1 - sqrt(f1)), and resume.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "services/engines/nsga2/nsga2_engine.h"
#include "services/engines/nsga2/nsga2_operators.h"
#include "services/engines/nsga2/pareto.h"

namespace gaitforge::engines::nsga2 {
namespace {

Evaluation Obj(double a, double b, double violation = 0) {
  Evaluation e{true, a + b, "", violation};
  e.objectives = {a, b};
  return e;
}

Bounds Unit(int n) {
  Bounds b;
  b.lo.assign(n, 0.0);
  b.hi.assign(n, 1.0);
  return b;
}

// ZDT1 as "higher is better": both objectives are minimised, so negated.
Evaluation Zdt1(const std::vector<double>& x) {
  double s = 0;
  for (size_t i = 1; i < x.size(); ++i) s += x[i];
  const double g = 1 + 9 * s / (x.size() - 1), f1 = x[0], f2 = g * (1 - std::sqrt(f1 / g));
  Evaluation e{true, -(f1 + f2), "", 0};
  e.objectives = {-f1, -f2};
  return e;
}

Nsga2Config ZdtConfig() {
  Nsga2Config c;
  c.seed = 7;
  c.population = 40;
  c.generations = 80;
  c.bounds = Unit(8);
  return c;
}

void RunGenerations(Nsga2Engine& e, int n) {
  for (int k = 0; k < n && !e.Done(); ++k) {
    std::vector<Evaluation> evals;
    for (const auto& c : e.Ask()) evals.push_back(Zdt1(c.genes));
    ASSERT_TRUE(e.Tell(evals).ok());
  }
}

TEST(Pareto, ConstrainedDominationFollowsDebsRule) {
  Evaluation invalid;
  EXPECT_TRUE(Dominates(Obj(0, 0, 5), invalid));
  EXPECT_FALSE(Dominates(invalid, Obj(0, 0, 5)));
  EXPECT_FALSE(Dominates(invalid, invalid));
  EXPECT_TRUE(Dominates(Obj(-9, -9), Obj(9, 9, 0.1)));     // feasible beats infeasible
  EXPECT_TRUE(Dominates(Obj(0, 0, 0.1), Obj(9, 9, 0.2)));  // smaller violation
  EXPECT_TRUE(Dominates(Obj(1, 2), Obj(1, 1)));
  EXPECT_FALSE(Dominates(Obj(1, 1), Obj(1, 1)));  // equal: neither
  EXPECT_FALSE(Dominates(Obj(2, 0), Obj(0, 2)));
  EXPECT_FALSE(Dominates(Obj(0, 2), Obj(2, 0)));
}

TEST(Pareto, FrontsAndCrowdingOfAHandWorkedSet) {
  // Front 0: (0,4) (1,2) (2,1) (4,0) as maxima; (0,1) and (1,0) lie under it; invalid last.
  std::vector<Evaluation> e = {Obj(0, 4), Obj(0, 1), Obj(1, 2),   Obj(2, 1),
                               Obj(1, 0), Obj(4, 0), Evaluation{}};
  const auto fronts = NondominatedFronts(e);
  ASSERT_EQ(fronts.size(), 3u);
  EXPECT_EQ(fronts[0], (std::vector<int>{0, 2, 3, 5}));
  EXPECT_EQ(fronts[1], (std::vector<int>{1, 4}));
  EXPECT_EQ(fronts[2], (std::vector<int>{6}));
  const auto d = CrowdingDistances(e, fronts[0]);
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(d[0], inf);
  EXPECT_EQ(d[3], inf);
  // (1,2): neighbours 0 and 2 in the first objective, 1 and 4 in the second, spans 4 and 4.
  EXPECT_DOUBLE_EQ(d[1], 2.0 / 4 + 3.0 / 4);
  EXPECT_DOUBLE_EQ(d[2], 3.0 / 4 + 2.0 / 4);
  EXPECT_EQ(CrowdingDistances(e, fronts[2])[0], 0.0);
}

TEST(Nsga2Operators, ChildrenStayInRangeAndRateZeroChangesNothing) {
  Bounds b = Unit(6);
  b.circular = {false, false, false, true, true, true};
  for (int k = 0; k < 200; ++k) {
    std::vector<double> x = {0.0, 0.5, 1.0, 0.02, 0.5, 0.97}, y = {1.0, 0.4, 0.9, 0.95, 0.1, 0.05};
    core::KeyedRng cross(1, k, 0, core::Purpose::kCrossover),
        mutate(1, k, 0, core::Purpose::kMutate);
    SbxCrossover(x, y, b, 1.0, 2.0, cross);
    PolynomialMutation(x, b, 1.0, 2.0, mutate);
    for (size_t i = 0; i < x.size(); ++i) {
      EXPECT_GE(x[i], 0.0);
      EXPECT_LE(x[i], b.IsCircular(i) ? std::nextafter(1.0, 0.0) : 1.0);
      EXPECT_GE(y[i], 0.0);
      EXPECT_LE(y[i], 1.0);
    }
  }
  std::vector<double> x = {0.2, 0.8}, y = {0.6, 0.1};
  core::KeyedRng r(1, 0, 0, core::Purpose::kCrossover);
  SbxCrossover(x, y, Unit(2), 0.0, 20, r);
  EXPECT_EQ(PolynomialMutation(x, Unit(2), 0.0, 20, r), 0);
  EXPECT_EQ(x, (std::vector<double>{0.2, 0.8}));
  EXPECT_EQ(y, (std::vector<double>{0.6, 0.1}));
}

TEST(Nsga2Operators, SbxOnACircularGeneCrossesTheSeamTheShortWay) {
  Bounds b = Unit(1);
  b.circular = {true};
  for (int k = 0; k < 100; ++k) {
    std::vector<double> x = {0.98}, y = {0.04};
    core::KeyedRng r(3, k, 0, core::Purpose::kCrossover);
    SbxCrossover(x, y, b, 1.0, 20, r);
    // Parents 0.06 apart across the seam: children near it, never near the middle.
    EXPECT_GT(std::abs(x[0] - 0.5), 0.3) << x[0];
    EXPECT_GT(std::abs(y[0] - 0.5), 0.3) << y[0];
  }
}

TEST(Nsga2Engine, FindsZdt1sFrontAcrossItsWholeSpan) {
  auto engine = Nsga2Engine::Create(ZdtConfig());
  ASSERT_TRUE(engine.ok()) << engine.status();
  RunGenerations(**engine, 80);
  ASSERT_TRUE((*engine)->Done());
  const auto front = (*engine)->HallOfFame();
  ASSERT_GE(front.size(), 30u);
  double lo = 1, hi = 0, gap = 0;
  for (const auto& h : front) {
    const double f1 = -h.eval.objectives[0], f2 = -h.eval.objectives[1];
    lo = std::min(lo, f1);
    hi = std::max(hi, f1);
    gap = std::max(gap, f2 - (1 - std::sqrt(f1)));  // distance above the true front
  }
  EXPECT_LT(lo, 0.05);
  EXPECT_GT(hi, 0.9);
  EXPECT_LT(gap, 0.1);
  for (size_t i = 1; i < front.size(); ++i)  // ordered by the first objective, best first
    EXPECT_GE(front[i - 1].eval.objectives[0], front[i].eval.objectives[0]);
}

TEST(Nsga2Engine, ResumedFromItsStateContinuesBitIdentically) {
  auto straight = Nsga2Engine::Create(ZdtConfig());
  auto first = Nsga2Engine::Create(ZdtConfig());
  ASSERT_TRUE(straight.ok() && first.ok());
  RunGenerations(**straight, 12);
  RunGenerations(**first, 5);
  auto resumed = Nsga2Engine::Create(ZdtConfig());
  ASSERT_TRUE((*resumed)->LoadState((*first)->SaveState()).ok());
  RunGenerations(**resumed, 7);
  EXPECT_EQ((*resumed)->SaveState(), (*straight)->SaveState());
  Nsga2Config other = ZdtConfig();
  other.seed = 8;
  auto stranger = Nsga2Engine::Create(other);
  EXPECT_FALSE((*stranger)->LoadState((*first)->SaveState()).ok());
  EXPECT_FALSE((*stranger)->LoadState("garbage").ok());
}

TEST(Nsga2Engine, InfeasibleAndInvalidMembersLeaveTheFront) {
  Nsga2Config c = ZdtConfig();
  c.population = 8;
  auto engine = Nsga2Engine::Create(c);
  std::vector<Evaluation> evals;
  for (int m = 0; m < 8; ++m) evals.push_back(m < 2 ? Obj(m, -m) : Obj(100, 100, 0.5));
  evals[7] = Evaluation{false, 0, "fell", 0};
  ASSERT_TRUE((*engine)->Tell(evals).ok());
  const auto front = (*engine)->HallOfFame();
  ASSERT_EQ(front.size(), 2u);
  EXPECT_EQ(front[0].member, 1);
  EXPECT_EQ(front[1].member, 0);
}

TEST(Nsga2Engine, RefusesAValidMemberWithoutItsObjectives) {
  auto engine = Nsga2Engine::Create(ZdtConfig());
  std::vector<Evaluation> evals(40, Obj(1, 1));
  evals[3].objectives = {1};
  EXPECT_FALSE((*engine)->Tell(evals).ok());
  evals[3].objectives = {1, std::nan("")};
  EXPECT_FALSE((*engine)->Tell(evals).ok());
  EXPECT_EQ((*engine)->generation(), 0);
  Nsga2Config bad = ZdtConfig();
  bad.objectives = 1;
  EXPECT_FALSE(Nsga2Engine::Create(bad).ok());
}

}  // namespace
}  // namespace gaitforge::engines::nsga2
