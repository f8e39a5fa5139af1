// A gait study from a calibration's fit (services/coordinator/from_calibration.h): which
// objective, which overrides, which ensemble ranges, and the refusals.
#include "services/coordinator/from_calibration.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>

#include "services/coordinator/corrected_model.h"
#include "services/spec/spec_validation.h"
#include "tests/unit/coordinator/calibration_fixture.h"

namespace gaitforge::coordinator {
namespace {

using ::testing::HasSubstr;

v1::StudySpec Gait(bool robust) {
  v1::StudySpec g;
  g.mutable_objective()->set_name("caterpillar.distance");
  (*g.mutable_objective()->mutable_options())["set"] = "effect.slope_rad=0.05";
  if (robust) g.mutable_objective()->mutable_robust();
  return g;
}

const std::vector<double> kBest = {9.6, 1.15, 0.01}, kSpread = {0.1, 0.5, 0.002};

TEST(FromCalibration, TheFitBecomesTheModelAndItsSpreadTheEnsemble) {
  v1::StudySpec c = Calibration("caterpillar.calibration");
  (*c.mutable_objective()->mutable_params())["timestep_ms"] = 0.5;
  v1::StudySpec g = Gait(true);
  ASSERT_TRUE(ApplyCalibration("cal-1", c, kBest, SpreadRanges(kBest, kSpread), &g).ok());
  const auto& o = g.objective();
  EXPECT_EQ(o.name(), "caterpillar.distance");
  // The fitted values first, the spec's own items after (they win); no nuisance.
  EXPECT_EQ(o.options().at("set"), "actuators.force_n=9.6,scale.link_stiffness=1.15,effect.slope_rad=0.05");
  EXPECT_EQ(o.params().at("timestep_ms"), 0.5);
  ASSERT_EQ(o.robust().parameters_size(), 2);
  EXPECT_EQ(o.robust().parameters(0).name(), "actuators.force_n");
  EXPECT_NEAR(o.robust().parameters(0).lo(), 9.4, 1e-12);
  EXPECT_NEAR(o.robust().parameters(0).hi(), 9.8, 1e-12);
  // +- 2 sd reaches past both bounds: clipped to the calibration's range.
  EXPECT_EQ(o.robust().parameters(1).lo(), 0.7);
  EXPECT_EQ(o.robust().parameters(1).hi(), 1.4);
}

// A log gene's spread is x sinh(s) (engines::LogGenesEngine): its range is x e^(+-2s),
// multiplicative and above zero, where x +- 2 spread would reach below zero.
TEST(FromCalibration, ALogGenesRangeIsTwoLogSpaceSdEachSide) {
  const double x = 0.01, s = 0.5;
  const auto ranges = SpreadRanges({x, 9.6}, {x * std::sinh(s), 0.1}, {true, false});
  ASSERT_EQ(ranges.size(), 2u);
  EXPECT_NEAR(ranges[0].lo, x * std::exp(-1.0), 1e-15);
  EXPECT_NEAR(ranges[0].hi, x * std::exp(1.0), 1e-15);
  EXPECT_NEAR(ranges[1].lo, 9.4, 1e-12);  // a linear gene as before
  EXPECT_GT(SpreadRanges({x}, {x * std::sinh(s)})[0].hi, 0.0);
  EXPECT_LT(SpreadRanges({x}, {x * std::sinh(s)})[0].lo, 0.0);  // unmarked: linear
}

// A gene the calibration searched by its logarithm is still sampled linearly over its range:
// measured (bench/transfer.py, 2026-12-02), sampling by the logarithm concentrated the
// members near a fit that had underestimated the build's creep, and gaits transferred
// worse on both builds. `log: true` on a range stays a choice the spec can make.
TEST(FromCalibration, ALogGenesEnsembleRangeIsSampledLinearly) {
  v1::StudySpec c = Calibration("caterpillar.calibration");
  c.mutable_bounds(1)->set_log(true);
  v1::StudySpec g = Gait(true);
  ASSERT_TRUE(ApplyCalibration("cal-1", c, kBest, SpreadRanges(kBest, kSpread), &g).ok());
  ASSERT_EQ(g.objective().robust().parameters_size(), 2);
  EXPECT_FALSE(g.objective().robust().parameters(0).log());
  EXPECT_EQ(g.objective().robust().parameters(1).name(), "scale.link_stiffness");
  EXPECT_FALSE(g.objective().robust().parameters(1).log());
}

// sampling: fits: the ensemble's parameters are the fitted values (no nuisance), its samples
// the fits themselves as joint values, best first, and the spec passes the validator.
TEST(FromCalibration, FitsBecomeJointSamplesOfTheFittedValues) {
  const v1::StudySpec c = Calibration("caterpillar.calibration");
  std::vector<std::vector<double>> fits = {{9.6, 1.15, 0.01}};
  for (int i = 0; i < 100; ++i)  // force and stiffness that trade off, as a fit's do
    fits.push_back({8.0 + 0.03 * i, 1.35 - 0.004 * i, -0.02});
  v1::StudySpec g = Gait(true);
  g.set_population(20);
  g.set_generations(1);
  g.mutable_objective()->set_from_calibration("cal-1");
  g.mutable_objective()->mutable_robust()->set_sampling("fits");
  ASSERT_TRUE(ApplyCalibration("cal-1", c, kBest, SpreadRanges(kBest, kSpread), &g).ok());
  EXPECT_EQ(g.objective().robust().parameters_size(), 0);  // no box ranges for fits
  ASSERT_TRUE(ApplyFits("cal-1", c, fits, &g).ok());
  const auto& r = g.objective().robust();
  ASSERT_EQ(r.parameters_size(), 2);
  EXPECT_EQ(r.parameters(1).name(), "scale.link_stiffness");
  EXPECT_EQ(r.samples_size(), static_cast<int>(kFitsPool));
  EXPECT_EQ(r.samples(0).values(0), 9.6);  // best first
  EXPECT_EQ(r.samples(0).values(1), 1.15);
  EXPECT_DOUBLE_EQ(r.parameters(0).lo(), 8.0);  // the extent of the pool: the ends are in it
  EXPECT_DOUBLE_EQ(r.parameters(0).hi(), 8.0 + 0.03 * 99);
  for (const auto& sample : r.samples()) {
    ASSERT_EQ(sample.values_size(), 2);
    if (sample.values(0) != 9.6) {  // a pair as fitted, not two independent draws
      EXPECT_NEAR(sample.values(1), 1.35 - 0.004 * (sample.values(0) - 8.0) / 0.03, 1e-9);
    }
  }
  spec::ApplyDefaults(&g);
  for (const auto& e : spec::Validate(g)) ADD_FAILURE() << e.path << ": " << e.message;
  // Submitted again (the stored spec): the same, not twice as many.
  ASSERT_TRUE(ApplyFits("cal-1", c, fits, &g).ok());
  EXPECT_EQ(g.objective().robust().samples_size(), static_cast<int>(kFitsPool));
}

TEST(FromCalibration, FitsRefuseAnUnfittedParameterAndACalibrationWithoutFits) {
  const v1::StudySpec c = Calibration("caterpillar.calibration");
  v1::StudySpec g = Gait(true);
  g.mutable_objective()->mutable_robust()->set_sampling("fits");
  AddEnsembleRange(g.mutable_objective(), "scale.mass", 0.9, 1.1);
  auto listed = ApplyFits("cal-1", c, {{9.6, 1.15, 0.0}}, &g);
  EXPECT_EQ(listed.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(listed.message(), HasSubstr("'scale.mass' is not a value calibration cal-1 fits"));
  v1::StudySpec plain = Gait(true);
  plain.mutable_objective()->mutable_robust()->set_sampling("fits");
  auto none = ApplyFits("cal-1", c, {}, &plain);
  EXPECT_EQ(none.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(none.message(), HasSubstr("sampling: fits needs per-recording errors"));
}

TEST(FromCalibration, WithoutRobustOrSpreadOnlyTheValuesAndTheSpecsOwnRangesStay) {
  v1::StudySpec g = Gait(false);
  ASSERT_TRUE(ApplyCalibration("cal-1", Calibration("caterpillar.calibration"), kBest, {}, &g).ok());
  EXPECT_FALSE(g.objective().has_robust());
  v1::StudySpec listed = Gait(true);
  AddEnsembleRange(listed.mutable_objective(), "actuators.force_n", 8.0, 8.5);
  ASSERT_TRUE(ApplyCalibration("cal-1", Calibration("caterpillar.calibration"), kBest, SpreadRanges(kBest, kSpread), &listed).ok());
  ASSERT_EQ(listed.objective().robust().parameters_size(), 2);
  EXPECT_EQ(listed.objective().robust().parameters(0).lo(), 8.0);  // the spec's own
}

TEST(FromCalibration, ARobotCalibrationGivesThatRobotsDistance) {
  v1::StudySpec c = Calibration("robot.calibration");
  c.mutable_objective()->set_robot("walker");
  (*c.mutable_objective()->mutable_options())["set"] = "ground.contact_cfm=2e-05";
  v1::StudySpec g;
  ASSERT_TRUE(ApplyCalibration("cal-2", c, kBest, SpreadRanges(kBest, kSpread), &g).ok());
  EXPECT_EQ(g.objective().name(), "robot.distance");
  EXPECT_EQ(g.objective().robot(), "walker");
  EXPECT_EQ(g.objective().options().at("set"),
            "ground.contact_cfm=2e-05,actuators.force_n=9.6,scale.link_stiffness=1.15");
}

TEST(FromCalibration, RefusesWhatIsNoCalibrationOrAnotherObjective) {
  v1::StudySpec g = Gait(false);
  auto not_cal = ApplyCalibration("ga-1", Gait(false), {0.1}, {}, &g);
  EXPECT_EQ(not_cal.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(not_cal.message(), HasSubstr("objective.from_calibration: study ga-1 is a caterpillar.distance study, not a calibration"));
  v1::StudySpec other;
  other.mutable_objective()->set_name("robot.distance");
  auto mismatch = ApplyCalibration("cal-1", Calibration("caterpillar.calibration"), kBest, {}, &other);
  EXPECT_EQ(mismatch.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(mismatch.message(), HasSubstr("gait objective is 'caterpillar.distance', not 'robot.distance'"));
  auto short_best = ApplyCalibration("cal-1", Calibration("caterpillar.calibration"), {9.6}, {}, &g);
  EXPECT_EQ(short_best.code(), absl::StatusCode::kFailedPrecondition);
}

// What the coordinator refuses before it reads a fit: both starting points at once, an id
// the database does not hold (NotFound: the CLI's exit 3), a calibration still running.
TEST(FromCalibration, RefusesBothStartsAnUnknownIdAndARunningStudy) {
  testing::TempDir dir;
  auto store = StoreWithCalibration(dir, "cal-running", "running");
  ASSERT_NE(store, nullptr);
  const SpreadFn spread = [](const std::string&, int) { return std::vector<double>{}; };
  auto resolve = [&](const std::string& id, const std::string& diagnosis) {
    v1::StudySpec g = Gait(true);
    g.mutable_objective()->set_from_calibration(id);
    g.mutable_objective()->set_from_diagnosis(diagnosis);
    return ResolveFromCalibration(*store, spread, &g);
  };
  auto both = resolve("cal-running", "diag-1");
  EXPECT_EQ(both.code(), absl::StatusCode::kInvalidArgument);
  EXPECT_THAT(both.message(), HasSubstr("from a calibration or from a diagnosis, not both"));
  auto unknown = resolve("cal-nowhere", "");
  EXPECT_EQ(unknown.code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(unknown.message(), HasSubstr("objective.from_calibration: no study with id 'cal-nowhere'"));
  auto not_done = resolve("cal-running", "");
  EXPECT_EQ(not_done.code(), absl::StatusCode::kFailedPrecondition);
  EXPECT_THAT(not_done.message(), HasSubstr("study cal-running is running; a study starts from a completed one"));
}

TEST(CorrectedModel, PrependSetKeepsTheSpecsItemsLastAndLeavesNoEmptySet) {
  v1::ObjectiveSpec o;
  PrependSet(&o, "");
  EXPECT_FALSE(o.options().count("set"));
  PrependSet(&o, "a=1");
  EXPECT_EQ(o.options().at("set"), "a=1");
  (*o.mutable_options())["set"] = "b=2";
  PrependSet(&o, "a=1");
  EXPECT_EQ(o.options().at("set"), "a=1,b=2");
  PrependSet(&o, "");
  EXPECT_EQ(o.options().at("set"), "a=1,b=2");
}

}  // namespace
}  // namespace gaitforge::coordinator
