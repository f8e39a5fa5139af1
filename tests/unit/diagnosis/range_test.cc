// The range search of the gap finder's magnitudes (services/diagnosis/range.h) on error
// functions whose answer is known: a bowl, a parameter the error ignores, a failing region.
#include "services/diagnosis/range.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

namespace gaitforge::diagnosis {
namespace {

// Error (x - 1)^2 + 0.25 (y - 2)^2: within 0.01 of its least for x in [0.9, 1.1] and y in
// [1.8, 2.2] (the ellipse's extent on each axis).
std::vector<double> Bowl(const std::vector<std::vector<double>>& points) {
  std::vector<double> e;
  for (const auto& p : points) e.push_back((p[0] - 1) * (p[0] - 1) + 0.25 * (p[1] - 2) * (p[1] - 2));
  return e;
}

RangeSearch Search(double tolerance, uint64_t seed = 7) {
  RangeSearch s;
  s.lo = {0, 0};
  s.hi = {3, 3};
  s.x0 = {1.02, 1.97};  // a fit near, not at, the least
  s.tolerance = tolerance;
  s.seed = seed;
  return s;
}

TEST(SearchRange, FindsTheSetWithinTheToleranceOfABowl) {
  const FitRange r = SearchRange(Search(0.01), Bowl);
  ASSERT_EQ(r.params.size(), 2u);
  // Inside the true extent (the accepted points are in the set) and covering most of it.
  EXPECT_GE(r.params[0].lo, 0.9);
  EXPECT_LE(r.params[0].lo, 0.94);
  EXPECT_LE(r.params[0].hi, 1.1);
  EXPECT_GE(r.params[0].hi, 1.06);
  EXPECT_GE(r.params[1].lo, 1.8);
  EXPECT_LE(r.params[1].lo, 1.88);
  EXPECT_LE(r.params[1].hi, 2.2);
  EXPECT_GE(r.params[1].hi, 2.12);
  EXPECT_FALSE(r.params[0].open_lo || r.params[0].open_hi || r.params[1].open_lo ||
               r.params[1].open_hi);
  EXPECT_GE(r.accepted, 8);
  EXPECT_LE(r.evaluations, 1 + 4 * 40 + 2 * 2 * (1 + 5));  // rounds, bounds, bisections
  // A looser tolerance, a wider range: sqrt(0.04) = 0.2 either side of x = 1.
  const FitRange wide = SearchRange(Search(0.04), Bowl);
  EXPECT_LT(wide.params[0].lo, r.params[0].lo);
  EXPECT_GT(wide.params[0].hi, r.params[0].hi);
  EXPECT_GE(wide.params[0].lo, 0.8);
}

TEST(SearchRange, AParameterTheErrorIgnoresSpansItsBoundsOrStaysOpen) {
  auto only_x = [](const std::vector<std::vector<double>>& points) {
    std::vector<double> e;
    for (const auto& p : points) e.push_back((p[0] - 1) * (p[0] - 1));
    return e;
  };
  // Bounds [0, 3]: the box grows to them, and the bounds themselves are tried: the range
  // is all of it, closed there.
  const FitRange r = SearchRange(Search(0.01), only_x);
  EXPECT_EQ(r.params[1].lo, 0);
  EXPECT_EQ(r.params[1].hi, 3);
  EXPECT_FALSE(r.params[1].open_lo || r.params[1].open_hi);
  // Bounds far away (+-1e6): steps past the box reach them, and they are accepted.
  RangeSearch far = Search(0.01);
  far.lo[1] = -1e6;
  far.hi[1] = 1e6;
  const FitRange all = SearchRange(far, only_x);
  EXPECT_EQ(all.params[1].lo, -1e6);
  EXPECT_EQ(all.params[1].hi, 1e6);
  // From a fit near the lower bound, this seed's rounds end early (enough accepted points,
  // none at the box's edge): the steps past the box, 15 box widths in all, reach no end and
  // not the bound. Open (RangeShare and RangeHolds take it to the bound), NAN end.
  RangeSearch near0 = Search(0.01, 5);
  near0.x0 = {1.0, 0.03};
  near0.hi[1] = 1e6;
  const FitRange open = SearchRange(near0, only_x);
  EXPECT_EQ(open.params[1].lo, 0);
  EXPECT_TRUE(open.params[1].open_hi);
  EXPECT_TRUE(std::isnan(open.params[1].hi));
  EXPECT_FALSE(open.params[0].open_lo || open.params[0].open_hi);
}

// An effect fitted small whose absence (its zero bound) the data cannot tell from the fit,
// as a deadband of 0.03 N the training error ignores below 0.3 N: the range reaches 0
// itself, so that it holds the value that leaves the model as it is (RangeHolds), though
// bisection alone stops 1/32 of the way short of the bound.
TEST(SearchRange, ReachesABoundTheDataCannotTellFromTheFit) {
  auto flat_near_zero = [](const std::vector<std::vector<double>>& points) {
    std::vector<double> e;
    for (const auto& p : points) {
      const double over = std::max(0.0, p[1] - 0.3);
      e.push_back((p[0] - 1) * (p[0] - 1) + over * over);
    }
    return e;
  };
  RangeSearch s = Search(0.01);
  s.x0 = {1.02, 0.03};
  const FitRange r = SearchRange(s, flat_near_zero);
  EXPECT_EQ(r.params[1].lo, 0);
  EXPECT_TRUE(RangeHolds(r.params[1], 0, 0, 3));
  EXPECT_LE(r.params[1].hi, 0.4);
  // A bound the data exclude is tried and refused: the range stays closed short of it.
  EXPECT_GT(r.params[0].lo, 0.85);
  EXPECT_FALSE(RangeHolds(r.params[0], 0, 0, 3));
}

// A set that goes on past the search's box: a tolerance so tight that one point in thirty
// is accepted (the box shrinks onto them), and an error that ignores y up to 0.4. The end is
// found past the box by steps and bisection (session 11: it was either 1/32 short of the
// box's edge, closed, or open where the accepted points touched the edge in the last round).
TEST(SearchRange, AnEndPastTheBoxIsFollowed) {
  auto flat_to_04 = [](const std::vector<std::vector<double>>& points) {
    std::vector<double> e;
    for (const auto& p : points) {
      const double over = std::max(0.0, p[1] - 0.4);
      e.push_back((p[0] - 1) * (p[0] - 1) + 100 * over * over);
    }
    return e;
  };
  RangeSearch s = Search(1e-4);
  s.x0 = {1.0, 0.03};
  const FitRange r = SearchRange(s, flat_to_04);
  EXPECT_EQ(r.params[1].lo, 0);
  EXPECT_FALSE(r.params[1].open_hi);
  EXPECT_GE(r.params[1].hi, 0.38);
  EXPECT_LE(r.params[1].hi, 0.401);
  EXPECT_GE(r.params[0].lo, 0.99);
  EXPECT_LE(r.params[0].hi, 1.01);
}

TEST(SearchRange, IsDeterministicPerSeedAndSkipsFailedPoints) {
  const FitRange a = SearchRange(Search(0.01, 42), Bowl);
  const FitRange b = SearchRange(Search(0.01, 42), Bowl);
  EXPECT_EQ(a.params[0].lo, b.params[0].lo);
  EXPECT_EQ(a.params[1].hi, b.params[1].hi);
  EXPECT_EQ(a.evaluations, b.evaluations);
  // The model fails (NAN) wherever x > 1.05: no accepted point lies there.
  auto failing = [](const std::vector<std::vector<double>>& points) {
    std::vector<double> e = Bowl(points);
    for (size_t i = 0; i < points.size(); ++i)
      if (points[i][0] > 1.05) e[i] = NAN;
    return e;
  };
  const FitRange f = SearchRange(Search(0.01, 42), failing);
  EXPECT_LE(f.params[0].hi, 1.05);
  EXPECT_GE(f.accepted, 1);
}

TEST(SearchRange, NoToleranceNoRange) {
  int calls = 0;
  auto counted = [&](const std::vector<std::vector<double>>& points) {
    ++calls;
    return Bowl(points);
  };
  const FitRange r = SearchRange(Search(NAN), counted);
  EXPECT_EQ(calls, 0);
  EXPECT_TRUE(std::isnan(r.params[0].lo));
  EXPECT_EQ(r.evaluations, 0);
}

TEST(TrainingTolerance, CombinesTheFilesFloorsByTheirWeights) {
  // sqrt(sum ((w_f / n) floor_f)^2), n = 2 files.
  EXPECT_NEAR(TrainingTolerance({0.5, 1.5}, {2e-3, 1e-3}),
              std::sqrt(std::pow(0.25 * 2e-3, 2) + std::pow(0.75 * 1e-3, 2)), 1e-15);
  EXPECT_NEAR(TrainingTolerance({}, {3e-4, 4e-4}), 2.5e-4, 1e-15);  // equal weights
  EXPECT_TRUE(std::isnan(TrainingTolerance({1.0}, {})));
}

TEST(RangeShare, TheShareOfTheAllowedValuesSpanned) {
  ParamRange r;
  EXPECT_TRUE(std::isnan(RangeShare(r, 0, 3)));  // not searched
  r.lo = 0.75;
  r.hi = 1.5;
  EXPECT_NEAR(RangeShare(r, 0, 3), 0.25, 1e-12);
  r.open_hi = true;  // reached the bound: spans to it
  EXPECT_NEAR(RangeShare(r, 0, 3), 0.75, 1e-12);
  // The foreign-soft rival's tether stiffness (session 8): 0.039 .. 50 N/m of 0 .. 50.
  EXPECT_GE(RangeShare({0.0393, 50, false, false}, 0, 50), kUndeterminedShare);
  // A soft-links stiffness scale, 0.569 .. 0.616 of 0.3 .. 3: pinned.
  EXPECT_LT(RangeShare({0.569, 0.616, false, false}, 0.3, 3), 0.05);
  // Four decades judged in log space, as they are searched: 1e-5 .. 1e-3 of 1e-6 .. 1e-2.
  EXPECT_NEAR(RangeShare({1e-5, 1e-3, false, false}, 1e-6, 1e-2), 0.5, 1e-12);
}

TEST(RangeHolds, OpenSidesReachTheBounds) {
  EXPECT_TRUE(RangeHolds({-0.3, 0.293, false, false}, 0, -0.3, 0.3));  // slope-steep's slope
  EXPECT_FALSE(RangeHolds({0.868, 2.29, false, false}, 0, 0, 3));       // deadband's band
  EXPECT_TRUE(RangeHolds({7.37, NAN, false, true}, 8.8, 3, 12));         // open above
  EXPECT_TRUE(RangeHolds({NAN, NAN, true, true}, 0, 0, 3));              // open both sides
  EXPECT_FALSE(RangeHolds(ParamRange{}, 0, 0, 3));                       // no range
}

Candidate PairWithForce() {
  Candidate c;
  c.effects = {"actuator.deadband", "actuator.force_scale"};
  for (const auto& [name, lo, hi, nominal, id] :
       {std::tuple{"effect.actuator_deadband_n", 0.0, 3.0, 0.0, "actuator.deadband"},
        std::tuple{"actuators.force_n", 3.0, 12.0, 8.8, "actuator.force_scale"},
        std::tuple{"nuisance.time_offset_s", -0.05, 0.05, 0.0, ""}}) {
    v1::GeneBound g;
    g.set_name(name);
    g.set_lo(lo);
    g.set_hi(hi);
    c.genes.push_back(g);
    c.mean0.push_back(nominal);
    c.nominal.push_back(nominal);
    c.gene_effect.push_back(id);
  }
  return c;
}

TEST(JudgeRange, SaysWhichEffectTheDataDoNotRequireOrPin) {
  // The shipped deadband case: the band is required, the force's range holds 8.8 N.
  FitRange r;
  r.params = {{0.868, 2.29, false, false}, {7.93, 11.8, false, false}, {}};
  RangeVerdict v = JudgeRange(PairWithForce(), r, 0);
  EXPECT_EQ(v.loose, "");
  EXPECT_EQ(v.unneeded, "actuators.force_n's range 7.93 .. 11.8 holds 8.8");
  EXPECT_EQ(v.unneeded_effects, std::vector<std::string>({"actuator.force_scale"}));
  // The foreign-lag case (session 9): the band open on both sides, neither required nor
  // pinned.
  r.params = {{NAN, NAN, true, true}, {7.37, NAN, false, true}, {}};
  v = JudgeRange(PairWithForce(), r, 0);
  EXPECT_EQ(v.loose, "effect.actuator_deadband_n (100%)");
  EXPECT_EQ(v.unneeded,
            "effect.actuator_deadband_n's range 0 (open) .. 3 (open) holds 0; "
            "actuators.force_n's range 7.37 .. 12 (open) holds 8.8");
  // Base parameters (before the first effect gene) are not judged.
  EXPECT_EQ(JudgeRange(PairWithForce(), r, 2).unneeded, "");
}

Candidate AnisotropicFriction() {
  Candidate c;
  c.effects = {"friction.anisotropic"};
  for (const char* name : {"effect.friction_forward", "effect.friction_backward"}) {
    v1::GeneBound g;
    g.set_name(name);
    g.set_lo(0);
    g.set_hi(3);
    c.genes.push_back(g);
    c.nominal.push_back(0.6);  // the walker's own coefficient: the effect absent
    c.mean0.push_back(0.6);
    c.gene_effect.push_back("friction.anisotropic");
  }
  return c;
}

TEST(JudgeRange, AnEffectIsUnneededOnlyWhenAllItsParametersHoldTheirNominal) {
  // The walker's anisotropic-3 (session 39): the forward coefficient pinned to 0.32 .. 0.42,
  // away from the model's 0.6, so the model without the effect is refused, though the
  // backward one's range, 0.446 .. 1.04, holds 0.6.
  FitRange r;
  r.params = {{0.323, 0.423, false, false}, {0.446, 1.04, false, false}};
  RangeVerdict v = JudgeRange(AnisotropicFriction(), r, 0);
  EXPECT_EQ(v.unneeded, "");
  EXPECT_TRUE(v.unneeded_effects.empty());
  // Both ranges hold 0.6: the data do not require the effect, and both are said.
  r.params[0] = {0.55, 0.7, false, false};
  v = JudgeRange(AnisotropicFriction(), r, 0);
  EXPECT_EQ(v.unneeded_effects, std::vector<std::string>({"friction.anisotropic"}));
  EXPECT_EQ(v.unneeded,
            "effect.friction_forward's range 0.55 .. 0.7 holds 0.6; "
            "effect.friction_backward's range 0.446 .. 1.04 holds 0.6");
}

TEST(JudgeRange, JudgesTheNominalNotWhereAWarmStartedFitBegan) {
  // A full fit warm-started from its screening fit (structure first) begins at the
  // screened values; whether the data require the effect is still judged at 0.6, the
  // effect absent: a range around where the fit began says nothing about that.
  Candidate c = AnisotropicFriction();
  c.mean0 = {0.37, 0.8};
  FitRange r;
  r.params = {{0.323, 0.423, false, false}, {0.446, 1.04, false, false}};
  RangeVerdict v = JudgeRange(c, r, 0);
  EXPECT_TRUE(v.unneeded_effects.empty());
  // Make keeps the nominal apart from the start.
  v1::DiagnosisSpec d;
  d.set_robot("caterpillar");
  Candidate made = Make(d, {"tether.constant"});
  ASSERT_EQ(made.nominal.size(), made.genes.size());
  EXPECT_EQ(made.nominal, made.mean0);
}

}  // namespace
}  // namespace gaitforge::diagnosis
