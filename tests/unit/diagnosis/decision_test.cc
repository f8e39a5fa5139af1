// The gap finder's decision rule on hand-made fit scores: a clear effect is found, noise is
// not, a pair must earn its extra parameters, near-ties are ambiguous.
#include "services/diagnosis/decision.h"

#include <cmath>

#include <gtest/gtest.h>

namespace gaitforge::diagnosis {
namespace {

FitScore Fit(std::vector<std::string> effects, double bic, std::vector<double> held) {
  FitScore f;
  f.effects = std::move(effects);
  f.ok = true;
  f.bic = bic;
  f.held_variants = std::move(held);
  double sum = 0;
  for (double h : f.held_variants) sum += h;
  f.held = sum / f.held_variants.size();
  return f;
}

// A baseline whose held-out error moves by tens of percent across the numeric variants.
FitScore Base() { return Fit({}, 0, {1.9, 2.5, 1.9, 1.8, 1.7, 1.7}); }

TEST(PairedT, SignAndDegenerateCases) {
  EXPECT_GT(PairedT({2, 3, 4}, {1, 2.1, 2.9}), 0);
  EXPECT_LT(PairedT({1, 2.1, 2.9}, {2, 3, 4}), 0);
  EXPECT_EQ(PairedT({2, 3}, {1, 2}), INFINITY);  // the same gain on every variant
  EXPECT_EQ(PairedT({1, 1}, {1, 1}), 0.0);
  EXPECT_TRUE(std::isnan(PairedT({1}, {0.5})));
  // Paired, not pooled: a consistent small gain on noisy errors is significant.
  EXPECT_NEAR(PairedT({1.0, 2.0, 3.0, 4.0}, {0.9, 1.9, 2.9, 3.85}), 9.0, 1e-9);
}

// A joint structure claims no missing physics: it must fit the training data better by the
// margin and must not predict the held-out recordings worse beyond the numeric spread; it
// need not cut the held-out error.
TEST(StructureAdmits, ABetterTrainingFitThatHoldsOutNoWorseThanTheSpread) {
  DecisionRule rule;
  rule.held_floor = 0.1;
  const FitScore base = Base();  // held 1.9167
  EXPECT_TRUE(StructureAdmits(base, Fit({"contact.softness"}, -50, {2.0, 2.0, 2.0, 2.0, 2.0, 2.0}), rule));
  EXPECT_FALSE(StructureAdmits(base, Fit({"contact.softness"}, -50, {2.1, 2.1, 2.1, 2.1, 2.1, 2.1}), rule));
  EXPECT_FALSE(StructureAdmits(base, Fit({"contact.softness"}, -5, {1.0, 1.0, 1.0, 1.0, 1.0, 1.0}), rule));
  FitScore failed = Fit({"contact.softness"}, -50, {1.0, 1.0, 1.0, 1.0, 1.0, 1.0});
  failed.ok = false;
  EXPECT_FALSE(StructureAdmits(base, failed, rule));
  // The discovery rule asks more of the same fit: a held-out gain.
  EXPECT_FALSE(BeatsBaseline(base, Fit({"contact.softness"}, -50, {2.0, 2.0, 2.0, 2.0, 2.0, 2.0}), rule));
}

TEST(Decide, NamesAClearEffect) {
  const std::vector<FitScore> fits = {Fit({"tether.constant"}, -4400, {0.5, 0.7, 0.7, 0.6, 0.6, 0.5}),
                                      Fit({"tether.growing"}, -2000, {1.9, 2.7, 1.7, 1.7, 1.6, 1.6})};
  const Decision d = Decide(Base(), fits, {});
  EXPECT_EQ(d.verdict, "found");
  ASSERT_EQ(d.named.size(), 1u);
  EXPECT_EQ(d.named[0], 0);
}

TEST(Decide, BicAloneIsNotADiscovery) {
  // A huge BIC gain (the rig's numerics differ from the model's) but the held-out error
  // only moves within its variant-to-variant spread: no discovery.
  const FitScore base = Fit({}, 0, {0.76, 0.62, 0.34, 0.66, 0.49, 0.45});
  const std::vector<FitScore> fits = {Fit({"tether.growing"}, -3100, {0.81, 0.39, 0.33, 0.63, 0.45, 0.42})};
  EXPECT_EQ(Decide(base, fits, {}).verdict, "none");
}

TEST(Decide, InconsistentHeldOutGainIsNotADiscovery) {
  // 20% lower on average, but worse on half of the variants: the paired test fails.
  const FitScore base = Fit({}, 0, {1, 1, 1, 1, 1, 1});
  const std::vector<FitScore> fits = {Fit({"ground.slope"}, -100, {0.3, 1.1, 0.4, 1.05, 0.35, 1.6})};
  EXPECT_LT(fits[0].held, 0.85 * base.held);
  EXPECT_EQ(Decide(base, fits, {}).verdict, "none");
}

TEST(Decide, NeedsTheBicMarginToo) {
  const std::vector<FitScore> fits = {Fit({"mass.offset"}, -5, {0.5, 0.7, 0.7, 0.6, 0.6, 0.5})};
  EXPECT_EQ(Decide(Base(), fits, {}).verdict, "none");
  FitScore failed = fits[0];
  failed.ok = false;
  EXPECT_EQ(Decide(Base(), {failed}, {}).verdict, "none");
}

TEST(Decide, APairMustBeatItsMember) {
  const FitScore single = Fit({"friction.viscous"}, -3840, {0.62, 0.52, 0.41, 0.68, 0.55, 0.61});
  // Better BIC, but the same held-out error: the single effect stands.
  const FitScore pair = Fit({"friction.viscous", "mass.offset"}, -4200,
                            {0.46, 0.65, 0.79, 0.55, 0.56, 0.50});
  Decision d = Decide(Base(), {pair, single}, {});
  EXPECT_EQ(d.verdict, "found");
  ASSERT_EQ(d.named.size(), 1u);
  EXPECT_EQ(d.named[0], 1);
  // Better BIC by the margin and 20% lower held out: the pair replaces it.
  const FitScore better = Fit({"friction.viscous", "mass.offset"}, -4200,
                              {0.45, 0.40, 0.33, 0.55, 0.45, 0.50});
  d = Decide(Base(), {single, better}, {});
  EXPECT_EQ(d.verdict, "found");
  ASSERT_EQ(d.named.size(), 1u);
  EXPECT_EQ(d.named[0], 1);
}

// The walker's deadband-1 at 0.5 ms against 0.25 ms recordings (session 38's figures, mm;
// variants: own step, 0.25, 0.375, 0.625 ms, CFM 3e-6, 3e-5): the pair with a 14 ms lag is
// 9% better on the mean but 3.5% under the finest step, where the deadband alone was named
// when the whole diagnosis ran there. With the finest step judged, the deadband stands.
TEST(Decide, APairMustAlsoBeatItsMemberAtTheFinestStep) {
  const FitScore base = Fit({}, 0, {20, 20, 20, 20, 20, 20});
  const FitScore deadband =
      Fit({"servo.deadband"}, -2421.85, {1.892, 1.677, 1.698, 2.103, 1.970, 1.950});
  const FitScore pair = Fit({"servo.deadband", "actuator.lag"}, -2469.57,
                            {1.835, 1.619, 1.624, 1.980, 1.617, 1.640});
  DecisionRule rule;
  Decision d = Decide(base, {deadband, pair}, rule);
  ASSERT_EQ(d.named.size(), 1u);
  EXPECT_EQ(d.named[0], 1);  // the mean alone: the pair
  rule.finest_step = 1;
  d = Decide(base, {deadband, pair}, rule);
  ASSERT_EQ(d.named.size(), 1u);
  EXPECT_EQ(d.named[0], 0);
  EXPECT_EQ(WhyNotNamed(base, pair, &deadband, rule, {&deadband, &pair}),
            "passed every test, but adds nothing the named explanation lacks (a larger fit "
            "must beat its member by the BIC margin and 5% held out, on the mean and at the "
            "finest step)");
  // A pair that wins at the finest step as well still replaces its member.
  FitScore strong = pair;
  strong.held_variants[1] = 1.4;
  d = Decide(base, {deadband, strong}, rule);
  EXPECT_EQ(d.named[0], 1);
  // A rule naming a variant the scores lack judges the mean alone.
  rule.finest_step = 9;
  EXPECT_EQ(Decide(base, {deadband, pair}, rule).named[0], 1);
}

TEST(Decide, TwoSinglesWithinTheMarginAreAmbiguous) {
  const std::vector<FitScore> fits = {Fit({"tether.constant"}, -3000, {0.5, 0.7, 0.7, 0.6, 0.6, 0.5}),
                                      Fit({"ground.slope"}, -2995, {0.6, 0.6, 0.7, 0.5, 0.6, 0.6})};
  const Decision d = Decide(Base(), fits, {});
  EXPECT_EQ(d.verdict, "ambiguous");
  EXPECT_EQ(d.named.size(), 2u);
  // Far apart in BIC: the better one is found.
  const std::vector<FitScore> apart = {fits[0], Fit({"ground.slope"}, -2000, {0.6, 0.6, 0.7, 0.5, 0.6, 0.6})};
  EXPECT_EQ(Decide(Base(), apart, {}).verdict, "found");
}

TEST(Decide, NamesThePassingFitThatPredictsTheHeldOutDataBest) {
  // The shipped soft-links case (session 5, mm): friction fits the training data better (its
  // hopping gait is chaos-dominated), the link stiffness halves the held-out error.
  const FitScore base = Fit({}, 0, {1.82, 1.54, 1.73, 1.89, 1.83, 1.84});
  const std::vector<FitScore> fits = {
      Fit({"friction.anisotropic"}, -2859, {1.41, 1.4, 1.39, 1.48, 1.41, 1.41}),
      Fit({"stiffness.scale"}, -2613, {0.71, 0.84, 0.91, 0.95, 1.02, 0.79}),
      Fit({"mass.offset"}, -2282, {1.56, 1.34, 1.52, 1.8, 1.45, 1.6})};
  ASSERT_TRUE(BeatsBaseline(base, fits[0], {}));
  ASSERT_TRUE(BeatsBaseline(base, fits[1], {}));
  const Decision d = Decide(base, fits, {});
  EXPECT_EQ(d.verdict, "found");
  ASSERT_EQ(d.named.size(), 1u);
  EXPECT_EQ(d.named[0], 1);
}

TEST(Decide, ARivalThatFitsFarBetterAndIsNotWorseHeldOutMakesItAmbiguous) {
  // The shipped lag case (session 5): drag passes every test; the actuator lag fails the
  // held-out gain but fits the training data far better and is not significantly worse
  // held out. Naming drag alone would be a wrong name.
  const FitScore base = Fit({}, 0, {1.23, 1.41, 1.2, 1.18, 1.19, 1.23});
  const std::vector<FitScore> fits = {
      Fit({"friction.viscous"}, -1990, {1.2, 0.96, 0.96, 1.05, 1.07, 1.04}),
      Fit({"actuator.lag"}, -8074, {1.35, 1.03, 0.69, 0.54, 1.04, 2.19}),
      Fit({"actuator.lag", "friction.viscous"}, -7860, {0.75, 1.33, 0.63, 0.83, 0.75, 2.16}),
      Fit({"actuator.deadband"}, -2208, {1.16, 1.24, 1.18, 1.24, 1.18, 1.24})};
  ASSERT_TRUE(BeatsBaseline(base, fits[0], {}));
  ASSERT_FALSE(BeatsBaseline(base, fits[1], {}));
  const Decision d = Decide(base, fits, {});
  EXPECT_EQ(d.verdict, "ambiguous");
  ASSERT_EQ(d.named.size(), 2u);
  EXPECT_EQ(d.named[0], 0);
  EXPECT_EQ(d.named[1], 1);  // the rival with the lowest BIC and no effect in common
  // A rival the held-out data show to be worse (paired t below -2.015) does not count: the
  // deadband's BIC is lower by 218, but it is worse on every variant.
  const std::vector<FitScore> worse = {fits[0], fits[3]};
  EXPECT_EQ(Decide(base, worse, {}).verdict, "found");
  // Nor does one sharing an effect with the winner (a refinement of it, judged as a pair).
  const std::vector<FitScore> sharing = {fits[0], fits[2]};
  EXPECT_EQ(Decide(base, sharing, {}).verdict, "found");
}

TEST(Decide, ARivalWorseHeldOutByLessThanTheNumericSpreadMakesItAmbiguous) {
  // The walker's slope-2 case (session 36, mm): a constant pull and the true slope fit the
  // training data alike (the slope's BIC lower by 20); the pull is better held out on every
  // numeric variant, but by 0.15 mm where the baseline's held-out error itself moves by
  // 0.2 mm across those variants: the held-out recording cannot tell a slope from a pull.
  const FitScore base = Fit({}, 0, {4.56, 4.94, 4.68, 4.38, 4.85, 4.73});
  const std::vector<FitScore> fits = {
      Fit({"tether.constant"}, -636.6, {1.83, 1.35, 1.34, 1.62, 1.49, 1.64}),
      Fit({"ground.slope"}, -656.1, {1.83, 1.69, 1.43, 1.70, 1.56, 1.97})};
  DecisionRule rule;
  ASSERT_LT(PairedT(fits[0].held_variants, fits[1].held_variants), -rule.paired_t);
  EXPECT_EQ(Decide(base, fits, rule).verdict, "found");  // without the spread: the pull
  rule.held_floor = 0.2;
  const Decision d = Decide(base, fits, rule);
  EXPECT_EQ(d.verdict, "ambiguous");
  ASSERT_EQ(d.named.size(), 2u);
  EXPECT_EQ(d.named[0], 0);
  EXPECT_EQ(d.named[1], 1);
  // Worse by more than the spread, it is no rival.
  rule.held_floor = 0.1;
  EXPECT_EQ(Decide(base, fits, rule).verdict, "found");
}

TEST(Decide, TwoSinglesApartByLessThanTheNumericSpreadAreATie) {
  // The walker's slope-1 case (session 36, mm): a constant pull and the true slope both pass;
  // the pull's training error is 0.04 mm lower, a BIC difference far past the margin, where
  // the model's own training error moves by 0.27 mm across the numeric variants; held out
  // they differ by 0.01 mm against a spread of 0.27.
  const FitScore base = Fit({}, 0, {4.1, 4.6, 4.3, 4.0, 4.5, 4.4});
  FitScore pull = Fit({"tether.constant"}, -700, {2.2, 1.9, 1.8, 2.1, 2.0, 2.2});
  FitScore slope = Fit({"ground.slope"}, -631, {2.1, 2.0, 1.9, 2.1, 2.0, 2.2});
  pull.train = 1.400;
  slope.train = 1.441;
  DecisionRule rule;
  EXPECT_EQ(Decide(base, {pull, slope}, rule).verdict, "found");  // BIC alone: the pull
  rule.train_floor = 0.27;
  rule.held_floor = 0.27;
  const Decision d = Decide(base, {pull, slope}, rule);
  EXPECT_EQ(d.verdict, "ambiguous");
  EXPECT_EQ(d.named.size(), 2u);
  // Apart by more than the spread on either, it is no tie.
  rule.train_floor = 0.03;
  EXPECT_EQ(Decide(base, {pull, slope}, rule).verdict, "found");
  rule.train_floor = 0.27;
  slope.held_variants = {2.6, 2.5, 2.4, 2.6, 2.5, 2.7};
  slope.held = 2.55;
  EXPECT_EQ(Decide(base, {pull, slope}, rule).verdict, "found");
}

TEST(SampleSd, NMinusOneAndDegenerateCases) {
  EXPECT_DOUBLE_EQ(SampleSd({}), 0);
  EXPECT_DOUBLE_EQ(SampleSd({3}), 0);
  EXPECT_NEAR(SampleSd({1, 2, 3, 4}), std::sqrt(5.0 / 3.0), 1e-12);
}

TEST(PreferDetermined, ARivalTheDataDoNotPinIsNoRival) {
  // The foreign-soft case (session 8): model.resolution first (pinned to 20.6 .. 23.8),
  // the rival friction.anisotropic + tether.growing free over nearly all its values.
  Decision d;
  d.verdict = "ambiguous";
  d.named = {3, 5};
  std::vector<int> dropped;
  Decision p = PreferDetermined(d, {false, true}, &dropped);
  EXPECT_EQ(p.verdict, "found");
  EXPECT_EQ(p.named, std::vector<int>({3}));
  EXPECT_EQ(dropped, std::vector<int>({5}));
  // Both pinned: still ambiguous, nothing dropped.
  dropped.clear();
  p = PreferDetermined(d, {false, false}, &dropped);
  EXPECT_EQ(p.verdict, "ambiguous");
  EXPECT_EQ(p.named, d.named);
  EXPECT_TRUE(dropped.empty());
  // The first named loose: it passed every test and is not dropped, nor is the rival
  // promoted: the ambiguity stands.
  p = PreferDetermined(d, {true, false}, &dropped);
  EXPECT_EQ(p.verdict, "ambiguous");
  EXPECT_EQ(p.named, d.named);
  // A found verdict is left alone, loose or not (the report says which parameter is free).
  Decision found;
  found.verdict = "found";
  found.named = {2};
  EXPECT_EQ(PreferDetermined(found, {true}, nullptr).named, found.named);
  EXPECT_EQ(PreferDetermined(Decision{}, {}, nullptr).verdict, "none");
  // Of three, only the loose one goes.
  d.named = {1, 4, 6};
  d.remainder_of = 7;  // kept
  p = PreferDetermined(d, {false, true, false}, nullptr);
  EXPECT_EQ(p.remainder_of, 7);
  EXPECT_EQ(p.verdict, "ambiguous");
  EXPECT_EQ(p.named, std::vector<int>({1, 6}));
}

TEST(DecideRequired, SetsAsideAFitTheDataDoNotRequireAndDecidesAgain) {
  // The shipped deadband case (session 8): the pair with a force scale is named, but the
  // force's range holds the model's 8.8 N; the deadband alone passed every test too.
  const FitScore base = Fit({}, 0, {0.9, 0.95, 0.85, 0.9, 0.92, 0.88});
  const std::vector<FitScore> fits = {
      Fit({"actuator.deadband"}, -3000, {0.5, 0.55, 0.48, 0.5, 0.53, 0.52}),
      Fit({"actuator.deadband", "actuator.force_scale"}, -3500, {0.42, 0.46, 0.41, 0.44, 0.45, 0.43}),
      Fit({"tether.constant"}, -2000, {0.8, 0.9, 0.7, 0.6, 0.8, 0.7})};
  ASSERT_EQ(Decide(base, fits, {}).named, std::vector<int>({1}));
  using Ids = std::vector<std::string>;
  std::vector<int> asked, aside;
  auto unneeded = [&](int i) {
    asked.push_back(i);
    return i == 1 ? Ids{"actuator.force_scale"} : Ids{};
  };
  Decision d = DecideRequired(base, fits, {}, unneeded, &aside);
  EXPECT_EQ(d.verdict, "found");
  EXPECT_EQ(d.named, std::vector<int>({0}));
  EXPECT_EQ(aside, std::vector<int>({1}));
  EXPECT_EQ(asked, std::vector<int>({1, 0}));
  EXPECT_EQ(d.remainder_of, 1);  // the deadband is what remains of the pair
  // Nothing required: nothing named (the slope paired with a growing tether on the shipped
  // slope-steep case, whose slope range holds 0, and no other fit passing).
  aside.clear();
  d = DecideRequired(base, {fits[1]}, {}, [](int) { return Ids{"actuator.deadband"}; }, &aside);
  EXPECT_EQ(d.verdict, "none");
  EXPECT_EQ(aside, std::vector<int>({0}));
  // Everything required: Decide's verdict.
  d = DecideRequired(base, fits, {}, [](int) { return Ids{}; }, nullptr);
  EXPECT_EQ(d.named, Decide(base, fits, {}).named);
  EXPECT_EQ(d.remainder_of, -1);
}

TEST(DecideRequired, NamesWhatRemainsOfASetAsideFitWhenItPassed) {
  // foreign-lag-strong (session 9): the lag with a force scale predicts the held-out gait
  // best, but the force's range holds the model's 8.8 N; of the rest the force scale alone
  // predicts it better than the lag alone. What the pair says is that the lag carries it.
  const FitScore base = Fit({}, 0, {1.6, 1.5, 1.6, 1.55, 1.5, 1.6});
  const std::vector<FitScore> fits = {
      Fit({"actuator.force_scale"}, -1900, {0.84, 0.87, 0.83, 1.03, 0.83, 0.86}),
      Fit({"actuator.lag", "actuator.force_scale"}, -2585, {0.52, 0.49, 0.52, 0.43, 1.02, 1.54}),
      Fit({"actuator.lag"}, -2492, {0.47, 0.47, 1.59, 0.67, 1.14, 1.65}),
      Fit({"actuator.deadband"}, -1887, {1.14, 1.03, 1.08, 1.15, 1.11, 1.1})};
  ASSERT_TRUE(BeatsBaseline(base, fits[2], {}));
  ASSERT_EQ(Decide(base, fits, {}).named[0], 1);
  using Ids = std::vector<std::string>;
  std::vector<int> aside;
  const Decision d = DecideRequired(
      base, fits, {}, [](int i) { return i == 1 ? Ids{"actuator.force_scale"} : Ids{}; }, &aside);
  EXPECT_EQ(d.verdict, "found");
  EXPECT_EQ(d.named, std::vector<int>({2}));
  EXPECT_EQ(d.remainder_of, 1);
  EXPECT_EQ(aside, std::vector<int>({1}));
  // Without the reduction the force scale alone, the wrong name, would win.
  std::vector<FitScore> without = fits;
  without[1].ok = false;
  EXPECT_EQ(Decide(base, without, {}).named[0], 0);
}

TEST(LeadersToRefit, TopAndItsNearTies) {
  // Screening errors of the foreign lag case (mm): the lag was 4th, 0.7% behind the 3rd.
  const std::vector<double> train = {1.90, 2.01, 2.045, 2.0595, 2.2, 2.21};
  EXPECT_EQ(LeadersToRefit(train, 3, 0.01), 4);
  EXPECT_EQ(LeadersToRefit(train, 3, 0.0), 3);   // no ties: exactly top
  EXPECT_EQ(LeadersToRefit(train, 3, 0.2), 5);   // at most two more
  EXPECT_EQ(LeadersToRefit(train, 3, 0.2, 1), 4);
  EXPECT_EQ(LeadersToRefit(train, 1, 0.1, 4), 4);  // ties are measured from the last leader
  EXPECT_EQ(LeadersToRefit({1.0, 1.0}, 5, 0.01), 2);  // fewer candidates than top
  EXPECT_EQ(LeadersToRefit({}, 3, 0.01), 0);
}

TEST(AtBound, EdgesButNotZero) {
  EXPECT_TRUE(AtBound(-0.3, -0.3, 0.3));    // a slope at the catalog's limit
  EXPECT_TRUE(AtBound(49.5, 0, 50));        // within 2% of the top
  EXPECT_FALSE(AtBound(41.6, 0, 50));
  EXPECT_FALSE(AtBound(0.0, 0, 2.5));       // zero is "no effect", a plausible value
  EXPECT_FALSE(AtBound(1e-5, 1e-6, 1e-2));  // four decades: judged in log space
  EXPECT_TRUE(AtBound(1.1e-6, 1e-6, 1e-2));
}

TEST(Decide, AFitAtTheEdgeOfItsRangeIsNoExplanation) {
  // The foreign null's false discovery: a growing tether with a slope pinned at -0.3 rad.
  FitScore pinned = Fit({"tether.growing", "ground.slope"}, -2352, {1.9, 1.5, 1.8, 1.8, 1.9, 1.9});
  const FitScore base = Fit({}, 0, {2.49, 1.98, 2.58, 2.6, 2.74, 2.77});
  EXPECT_EQ(Decide(base, {pinned}, {}).verdict, "found");
  pinned.at_bound = true;
  EXPECT_EQ(Decide(base, {pinned}, {}).verdict, "none");
}

// Every runner-up gets the first test it failed, with its figures.
TEST(WhyNotNamed, SaysWhichTestFailedWithItsFigures) {
  const FitScore base = Fit({}, 0, {1, 1, 1, 1, 1, 1});
  const FitScore winner = Fit({"tether.constant"}, -400, {0.5, 0.5, 0.6, 0.5, 0.5, 0.6});
  const DecisionRule rule;
  EXPECT_EQ(WhyNotNamed(base, winner, &winner, rule), "");
  FitScore failed = winner;
  failed.ok = false;
  EXPECT_EQ(WhyNotNamed(base, failed, &winner, rule), "the fit failed (no valid model)");
  FitScore pinned = Fit({"ground.slope"}, -500, {0.5, 0.5, 0.5, 0.5, 0.5, 0.5});
  pinned.at_bound = true;
  EXPECT_NE(WhyNotNamed(base, pinned, &winner, rule).find("edge of its range"), std::string::npos);
  EXPECT_EQ(WhyNotNamed(base, Fit({"mass.offset"}, -5, {0.5, 0.5, 0.5, 0.5, 0.5, 0.5}), &winner,
                        rule),
            "fits the training data no better than the baseline (delta BIC -5.0; the rule asks "
            "below -10)");
  EXPECT_EQ(WhyNotNamed(base, Fit({"tether.growing"}, -2000, {1.6, 1.6, 1.6, 1.6, 1.6, 1.7}),
                        &winner, rule),
            "fits the training data better (delta BIC -2000) but predicts the held-out "
            "recordings worse (+62%): it absorbs the training mismatch");
  EXPECT_EQ(WhyNotNamed(base, Fit({"friction.viscous"}, -300, {0.94, 0.94, 0.94, 0.94, 0.94, 0.94}),
                        &winner, rule),
            "cuts the held-out error by only 6% (the rule asks 15%)");
  EXPECT_EQ(WhyNotNamed(base, Fit({"ground.slope"}, -100, {0.3, 1.1, 0.4, 1.05, 0.35, 1.6}),
                        &winner, rule),
            "cuts the held-out error by 20% on average, but not consistently across the numeric "
            "variants (paired t 0.92, the rule asks above 2.015)");
  EXPECT_EQ(WhyNotNamed(base, Fit({"tether.constant", "mass.offset"}, -405, {0.5, 0.5, 0.5, 0.5, 0.5, 0.5}),
                        &winner, rule),
            "passed every test, but adds nothing the named explanation lacks (a larger fit must "
            "beat its member by the BIC margin and 5% held out)");
  EXPECT_EQ(WhyNotNamed(base, Fit({"friction.viscous"}, -390, {0.6, 0.6, 0.6, 0.6, 0.6, 0.6}),
                        &winner, rule),
            "passed every test, but the named explanation predicts the held-out recordings better "
            "(533 against 600 mm)");
}

// A pair dropped for its member, while another single is named (a sparse capture of the
// independent simulator's 80 ms lag): the pair predicts the held-out data better than the
// named force scale, so "the named explanation predicts better" would be false.
TEST(WhyNotNamed, APairDroppedForItsMemberSaysSoWhoeverIsNamed) {
  const FitScore base = Fit({}, 0, {2, 2, 2, 2, 2, 2});
  const FitScore force = Fit({"actuator.force_scale"}, -352, {1.1, 1.2, 1.1, 1.1, 1.1, 1.1});
  const FitScore lag = Fit({"actuator.lag"}, -541, {1.2, 1.1, 1.2, 1.1, 1.2, 1.2});
  const FitScore pair =
      Fit({"actuator.lag", "actuator.deadband"}, -535, {0.7, 0.7, 0.6, 0.7, 0.7, 0.8});
  const DecisionRule rule;
  EXPECT_EQ(WhyNotNamed(base, pair, &force, rule, {&force, &lag, &pair}),
            "passed every test, but adds nothing its member actuator.lag lacks (a larger fit "
            "must beat its member by the BIC margin and 5% held out)");
  // Without the member among the others, the old words (and they would be false here).
  EXPECT_NE(WhyNotNamed(base, pair, &force, rule).find("predicts the held-out recordings better"),
            std::string::npos);
}

}  // namespace
}  // namespace gaitforge::diagnosis
