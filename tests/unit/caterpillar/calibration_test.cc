// Calibration of the caterpillar model against recordings: the calibratable parameter names
// (param_overrides.h), the error measures with hand-computed values (calibration_error.h), and
// a round trip of "caterpillar.calibration" (calibration_objective.h) on a recording made in
// memory from the model with known parameters, a constant offset on every x channel and a
// time shift.
#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_format.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "services/recording/recording.h"
#include "workers/objectives/calibration_error.h"
#include "workers/models/caterpillar/calibration_objective.h"
#include "workers/models/caterpillar/caterpillar_eval.h"
#include "workers/models/caterpillar/caterpillar_params.h"
#include "workers/models/caterpillar/gait.h"
#include "workers/models/caterpillar/param_overrides.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::caterpillar {
namespace {

using ::testing::HasSubstr;
namespace cal = calibration;

const CaterpillarParams& Defaults() { return DefaultCaterpillarParams(); }

// ---------------------------------------------------------------------------------------
// Parameter overrides

TEST(CalibrationParams, SetsAbsoluteFields) {
  CaterpillarParams p = Defaults();
  ASSERT_TRUE(SetParam(p, "actuators.force_n", 7.5).ok());
  EXPECT_EQ(p.actuators.force_n, 7.5);
  ASSERT_TRUE(SetParam(p, "lumps.mass_kg", 0.04).ok());
  EXPECT_EQ(p.lumps.mass_kg, 0.04);
  ASSERT_TRUE(SetParam(p, "ground.contact_cfm", 2e-5).ok());
  EXPECT_EQ(p.ground.contact_cfm, 2e-5);
  ASSERT_TRUE(p.ground.infinite_friction);
  ASSERT_TRUE(SetParam(p, "ground.friction_coefficient", 0.6).ok());
  EXPECT_EQ(p.ground.friction_coefficient, 0.6);
  EXPECT_FALSE(p.ground.infinite_friction);
}

TEST(CalibrationParams, ScalesMultiplyGroups) {
  const CaterpillarParams& d = Defaults();
  CaterpillarParams p = d;
  ASSERT_TRUE(SetParam(p, "scale.link_stiffness", 2.0).ok());
  EXPECT_EQ(p.links.flexure.axial_n_per_m, 2 * d.links.flexure.axial_n_per_m);
  EXPECT_EQ(p.links.flexure.bending_nm_per_rad, 2 * d.links.flexure.bending_nm_per_rad);
  EXPECT_EQ(p.links.segment.axial_n_per_m, 2 * d.links.segment.axial_n_per_m);
  EXPECT_EQ(p.links.segment.bending_nm_per_rad, 2 * d.links.segment.bending_nm_per_rad);
  ASSERT_TRUE(SetParam(p, "scale.bending_stiffness", 0.5).ok());  // applied on top
  EXPECT_EQ(p.links.flexure.bending_nm_per_rad, d.links.flexure.bending_nm_per_rad);
  EXPECT_EQ(p.links.flexure.axial_n_per_m, 2 * d.links.flexure.axial_n_per_m);
  ASSERT_TRUE(SetParam(p, "scale.axial_stiffness", 0.5).ok());
  EXPECT_EQ(p.links.segment.axial_n_per_m, d.links.segment.axial_n_per_m);
  ASSERT_TRUE(SetParam(p, "scale.mass", 1.5).ok());
  EXPECT_DOUBLE_EQ(p.lumps.mass_kg, 1.5 * d.lumps.mass_kg);
}

TEST(CalibrationParams, RejectsOutOfRangeUnknownAndNuisance) {
  CaterpillarParams p = Defaults();
  absl::Status s = SetParam(p, "actuators.force_n", 120);
  EXPECT_FALSE(s.ok());
  EXPECT_THAT(std::string(s.message()),
              HasSubstr("actuators.force_n = 120 N is outside [0, 100] N"));
  EXPECT_FALSE(SetParam(p, "links.axial_damping_ratio", NAN).ok());
  EXPECT_FALSE(SetParam(p, "scale.mass", 0).ok());
  EXPECT_FALSE(SetParam(p, "scale.mass", -1).ok());
  // 1040 N/m * 1e4 leaves [1, 1e6]; nothing changes.
  s = SetParam(p, "scale.link_stiffness", 1e4);
  EXPECT_FALSE(s.ok());
  EXPECT_THAT(std::string(s.message()), HasSubstr("links.flexure.axial_stiffness_n_per_m"));
  EXPECT_EQ(p.links.flexure.axial_n_per_m, Defaults().links.flexure.axial_n_per_m);
  // The stroke stop below the rest length.
  s = SetParam(p, "actuators.max_length_m", 0.04);
  EXPECT_FALSE(s.ok());
  EXPECT_THAT(std::string(s.message()),
              HasSubstr("relation 'actuators.max_length_m > actuators.min_length_m' fails"));

  s = SetParam(p, "actuators.forse_n", 1);
  EXPECT_FALSE(s.ok());
  EXPECT_THAT(std::string(s.message()), HasSubstr("nearest: actuators.force_n"));
  EXPECT_THAT(std::string(s.message()), HasSubstr("scale.link_stiffness"));
  EXPECT_THAT(std::string(s.message()), HasSubstr("nuisance.time_offset_s"));
  EXPECT_FALSE(SetParam(p, kTimeOffsetParam, 0.1).ok());
  EXPECT_TRUE(IsNuisanceParam("nuisance.time_offset_s"));
}

TEST(CalibrationParams, EveryListedNameIsSettable) {
  for (const std::string& name : CalibratableParamNames()) {
    CaterpillarParams p = Defaults();
    const double v = name.rfind("scale.", 0) == 0                        ? 1.1
                     : name == "actuators.max_length_m"                  ? 0.06
                     : name == "ground.contact_cfm"                      ? 1e-4
                     : name.rfind("effect.", 0) == 0                     ? 0.1
                     : name == "simulation.timestep_s"                   ? 5e-4
                     : name.find("axial_stiffness") != std::string::npos ? 500
                                                                         : 0.5;
    EXPECT_TRUE(SetParam(p, name, v).ok()) << name;
  }
}

// ---------------------------------------------------------------------------------------
// Error measures (hand-computed)

TEST(CalibrationError, MaeRmseMedianAndOffsets) {
  const std::vector<double> a = {1, 2, 3}, b = {1, 1, 1};
  EXPECT_DOUBLE_EQ(cal::Mae(a, b), 1.0);                  // (0 + 1 + 2) / 3
  EXPECT_DOUBLE_EQ(cal::Rmse(a, b), std::sqrt(5.0 / 3));  // (0 + 1 + 4) / 3
  EXPECT_DOUBLE_EQ(cal::Median({3, 1, 2}), 2.0);
  EXPECT_DOUBLE_EQ(cal::Median({4, 1, 3, 2}), 2.5);
  const std::vector<double> real = {1, 2, 6}, zero = {0, 0, 0};
  EXPECT_DOUBLE_EQ(cal::ProfiledOffset(cal::Metric::kRmse, real, zero), 3.0);  // mean
  EXPECT_DOUBLE_EQ(cal::ProfiledOffset(cal::Metric::kMae, real, zero), 2.0);   // median
  // Pooled over channels: channel 0 is off by a constant (profiled away), channel 1 has
  // residuals {1, -1} after its mean 0.
  std::vector<double> offsets;
  const double e = cal::PooledError(cal::Metric::kRmse, {{1, 2}, {1, -1}}, {{0, 1}, {0, 0}}, 0, 2,
                                    0, true, &offsets);
  EXPECT_DOUBLE_EQ(e, std::sqrt(2.0 / 4));  // (0 + 0 + 1 + 1) / 4
  EXPECT_THAT(offsets, ::testing::ElementsAre(1.0, 0.0));
  // Without profiling: residuals 1, 1, 1, -1.
  EXPECT_DOUBLE_EQ(
      cal::PooledError(cal::Metric::kMae, {{1, 2}, {1, -1}}, {{0, 1}, {0, 0}}, 0, 2, 0, false),
      1.0);
}

TEST(CalibrationError, ShiftInvariantFindsTheShiftAndOffset) {
  // real[2] = 1 pairs with sim[3] = 1: shift +1; sim also 5 higher (offset -5).
  const cal::Signals real = {{0, 0, 1, 0, 0, 0}};
  const cal::Signals sim = {{5, 5, 5, 6, 5, 5}};
  const auto r = cal::ShiftInvariantError(cal::Metric::kMae, real, sim, 2, true);
  EXPECT_EQ(r.shift, 1);
  EXPECT_DOUBLE_EQ(r.error, 0.0);
  ASSERT_EQ(r.offsets.size(), 1u);
  EXPECT_DOUBLE_EQ(r.offsets[0], -5.0);
  // Without profiling the constant 5 stays: MAE 5 at every shift; ties go to shift 0.
  const auto r0 = cal::ShiftInvariantError(cal::Metric::kMae, real, {{0, 0, 0, 0, 0, 0}}, 2, false);
  EXPECT_EQ(r0.shift, 0);
  EXPECT_DOUBLE_EQ(r0.error, 1.0 / 6);
  // The peak 2 samples later: found with max_shift 2 (the overlap at s = 2 is
  // real[0..4] = sim[2..6]), not with max_shift 1.
  const cal::Signals early = {{0, 1, 0, 0, 0, 0, 0}}, late = {{0, 0, 0, 1, 0, 0, 0}};
  const auto r2 = cal::ShiftInvariantError(cal::Metric::kRmse, early, late, 2, false);
  EXPECT_EQ(r2.shift, 2);
  EXPECT_DOUBLE_EQ(r2.error, 0.0);
  const auto r1 = cal::ShiftInvariantError(cal::Metric::kRmse, early, late, 1, false);
  EXPECT_GT(r1.error, 0.0);
  // The other way round: shift -2.
  EXPECT_EQ(cal::ShiftInvariantError(cal::Metric::kRmse, late, early, 2, false).shift, -2);
}

TEST(CalibrationError, PaddedShiftComparesEverySample) {
  // real[i] pairs with sim[i + 1 + s]; {1, 2, 3} sits at sim[0..2]: s = -1.
  const auto r =
      cal::PaddedShiftInvariantError(cal::Metric::kRmse, {{1, 2, 3}}, {{1, 2, 3, 9, 9}}, 1, false);
  EXPECT_EQ(r.shift, -1);
  EXPECT_DOUBLE_EQ(r.error, 0.0);
  // With offsets: {2, 3, 4} at s = 0 is real - 1 ... plus 1: offset -1.
  const auto p =
      cal::PaddedShiftInvariantError(cal::Metric::kRmse, {{1, 2, 3}}, {{9, 2, 3, 4, 9}}, 1, true);
  EXPECT_EQ(p.shift, 0);
  EXPECT_DOUBLE_EQ(p.error, 0.0);
  EXPECT_THAT(p.offsets, ::testing::ElementsAre(-1.0));
  // Hand-computed, offsets profiled, sim {9, 2, 3, 9, 9}:
  //   s = -1: {9, 2, 3}: residuals -8, 0, 0, mean -8/3 -> -16/3, 8/3, 8/3: RMSE sqrt(384/27)
  //   s =  0: {2, 3, 9}: residuals -1, -1, -6, mean -8/3 -> 5/3, 5/3, -10/3: sqrt(150/27)
  //   s = +1: {3, 9, 9}: residuals -2, -7, -6, mean -5 -> 3, -2, -1: sqrt(14/3), the best.
  const auto q =
      cal::PaddedShiftInvariantError(cal::Metric::kRmse, {{1, 2, 3}}, {{9, 2, 3, 9, 9}}, 1, true);
  EXPECT_EQ(q.shift, 1);
  EXPECT_NEAR(q.error, std::sqrt(14.0 / 3), 1e-12);
  EXPECT_THAT(q.offsets, ::testing::ElementsAre(-5.0));
  EXPECT_NEAR(cal::PooledError(cal::Metric::kRmse, {{1, 2, 3}}, {{9, 2, 3, 9, 9}}, 0, 3, 1, true),
              std::sqrt(150.0 / 27), 1e-12);
}

std::pair<int64_t, int64_t> Cycles(int64_t begin, int64_t end) { return {begin, end}; }

TEST(CalibrationError, InterpolationAndCycles) {
  const std::vector<double> t = {0, 1, 2}, x = {0, 10, 0};
  EXPECT_DOUBLE_EQ(cal::Interpolate(t, x, 0.5), 5.0);
  EXPECT_DOUBLE_EQ(cal::Interpolate(t, x, 1.0), 10.0);
  EXPECT_DOUBLE_EQ(cal::Interpolate(t, x, 1.25), 7.5);
  EXPECT_DOUBLE_EQ(cal::Interpolate(t, x, -1), 0.0);
  EXPECT_DOUBLE_EQ(cal::Interpolate(t, x, 3), 0.0);
  EXPECT_EQ(cal::BinsPerPeriod(0.8, 0.01), 80);
  EXPECT_EQ(cal::BinsPerPeriod(0.805, 0.01), 81);  // round(80.5)
  EXPECT_EQ(cal::BinsPerPeriod(0.01, 0.01), 2);
  // Period 1 in 10 bins: cycle k's last bin is at k + 0.9.
  EXPECT_EQ(cal::WholeCycles(0, 1.95, 1.0, 10, 0), Cycles(0, 2));
  EXPECT_EQ(cal::WholeCycles(0, 1.9, 1.0, 10, 0), Cycles(0, 2));
  EXPECT_EQ(cal::WholeCycles(0, 1.85, 1.0, 10, 0), Cycles(0, 1));
  EXPECT_EQ(cal::WholeCycles(0.05, 2.95, 1.0, 10, 0), Cycles(1, 3));
  EXPECT_EQ(cal::WholeCycles(0.05, 2.95, 1.0, 10, 0.05), Cycles(0, 3));
  const auto none = cal::WholeCycles(0.5, 1.2, 1.0, 10, 0);
  EXPECT_EQ(none.first, none.second);
}

TEST(CalibrationError, PeriodAveragingKeepsShapeAndDrift) {
  // x = i mod 4 + 10 * cycle, dt = 1, T = 4, 13 samples: 3 whole cycles (the 13th sample
  // starts a 4th): average i + 10 * (0 + 1 + 2) / 3.
  std::vector<double> x;
  for (int i = 0; i < 13; ++i) x.push_back(i % 4 + 10 * (i / 4));
  EXPECT_THAT(cal::PeriodAverageSampled(x, 1.0, 4.0), ::testing::ElementsAre(10, 11, 12, 13));
  // Padding: the ramp x = t over cycle 1 with one bin either side: times 3 .. 8.
  std::vector<double> t(12), ramp(12);
  for (int i = 0; i < 12; ++i) t[i] = ramp[i] = i;
  EXPECT_THAT(cal::PeriodAverage(t, ramp, 4.0, 4, 0.0, 1, 2, 1),
              ::testing::ElementsAre(3, 4, 5, 6, 7, 8));
  // Origin 0.5: times 0.5 + 4k + i, averaged over k = 0, 1: 2.5 + i.
  EXPECT_THAT(cal::PeriodAverage(t, ramp, 4.0, 4, 0.5, 0, 2),
              ::testing::ElementsAre(2.5, 3.5, 4.5, 5.5));
  EXPECT_TRUE(cal::PeriodAverage(t, ramp, 4.0, 4, 0.0, 2, 2).empty());
}

TEST(CalibrationError, SlopeAndDistancePerCycle) {
  const std::vector<double> t4 = {0, 1, 2, 3};
  EXPECT_DOUBLE_EQ(cal::LeastSquaresSlope(t4, std::vector<double>{1, 3, 5, 7}), 2.0);
  // mean t 1.5, mean x 1; sum dt dx = 1.5 + 0 + 0 + 1.5 = 3; sum dt^2 = 5.
  EXPECT_DOUBLE_EQ(cal::LeastSquaresSlope(t4, std::vector<double>{0, 1, 1, 2}), 0.6);
  EXPECT_THAT(cal::MeanSignal({{1, 2}, {3, 6}}), ::testing::ElementsAre(2, 4));
  // 1 cm per cycle of 0.5 s plus a 3 mm oscillation at the gait period, over 20 cycles.
  std::vector<double> t, x;
  for (int i = 0; i < 1000; ++i) {
    t.push_back(i * 0.01);
    x.push_back(0.02 * t.back() + 0.003 * std::cos(2 * std::numbers::pi * t.back() / 0.5));
  }
  EXPECT_NEAR(cal::DistancePerCycle(t, x, 0.5), 0.01, 1e-5);
}

// ---------------------------------------------------------------------------------------
// The objective: a round trip on a simulated recording

constexpr double kPeriod = 0.8;
constexpr double kDt = 0.01;       // 100 Hz
constexpr int kCycles = 12;        // recorded cycles after 2 settle cycles
constexpr double kOffsetX = 0.02;  // added to every m*.x channel (m)
constexpr int kShiftSamples = 3;   // the recording's clock runs 3 samples behind

std::vector<double> Genes() { return TravellingWaveGenes(kPeriod); }

// A recording of the model with `p`, made like gaitforge-sim trajectory: markers over the
// measured cycles after 2 settle cycles, t absolute from rest; then x_offset added to every
// x channel and t reduced by time_shift.
std::shared_ptr<const recording::Recording> MakeRecording(const CaterpillarParams& p,
                                                          double x_offset, double time_shift) {
  sim::InitThread();
  EvalOptions o;
  o.settle_cycles = 2;
  o.measured_cycles = kCycles;
  o.marker_rate_hz = 1 / kDt;
  const GaitEvaluation e = EvaluateGait(p, *Gait::FromGenes(Genes()), o);
  EXPECT_TRUE(e.valid) << e.reason;
  auto rec = std::make_shared<recording::Recording>();
  rec->meta.robot = "caterpillar";
  rec->meta.command_kind = "gait";
  rec->meta.genes = Genes();
  rec->meta.source = "simulation";
  rec->dt = kDt;
  for (double t : e.markers.t) rec->t.push_back(t - time_shift);
  for (int i = 0; i < 6; ++i) {
    for (const char* axis : {"x", "y", "z"}) {
      rec->channels.push_back("m" + std::to_string(i + 1) + "." + axis);
      const auto& src = axis[0] == 'x'   ? e.markers.x[i]
                        : axis[0] == 'y' ? e.markers.y[i]
                                         : e.markers.z[i];
      std::vector<double> col = src;
      if (axis[0] == 'x') {
        for (double& v : col) v += x_offset;
      }
      rec->columns.push_back(std::move(col));
    }
  }
  return rec;
}

// The recording with the injected offset and shift, made once.
std::shared_ptr<const recording::Recording> TrueRecording() {
  static const auto rec = MakeRecording(Defaults(), kOffsetX, kShiftSamples * kDt);
  return rec;
}

objectives::EvalInput Input(double force_n, double stiffness_scale, const std::string& error,
                            const std::string& metric = "rmse") {
  objectives::EvalInput in;
  in.gene_names = {"actuators.force_n", "scale.link_stiffness"};
  in.genes = {force_n, stiffness_scale};
  in.lo = {4, 0.25};
  in.hi = {16, 4};
  in.options = {{"error", error}, {"metric", metric}};
  in.recordings = {TrueRecording()};
  return in;
}

objectives::EvalResult Eval(const objectives::EvalInput& in) {
  return CalibrationObjective(Defaults()).Evaluate(in);
}

TEST(CalibrationObjective, RecordingMovesAndTrueParametersMatchInShape) {
  const auto r = Eval(Input(8.8, 1.0, "shape"));
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_LT(r.metrics.at("error"), 1e-9);
  EXPECT_EQ(r.fitness, -r.metrics.at("error"));
  EXPECT_EQ(r.metrics.at("best_shift_0"), kShiftSamples);
  EXPECT_NEAR(r.metrics.at("time_shift_s_0"), kShiftSamples * kDt, 1e-12);
  EXPECT_NEAR(r.metrics.at("offset_x"), kOffsetX, 1e-9);
  EXPECT_NEAR(r.metrics.at("offset_y"), 0, 1e-9);
  EXPECT_NEAR(r.metrics.at("offset_z"), 0, 1e-9);
  // The robot travels (about -0.7 mm per cycle: this model's travelling wave at 0.8 s
  // barely moves) and both agree once the shift is applied.
  EXPECT_GT(std::fabs(r.metrics.at("real_distance_per_cycle_0")), 2e-4);
  EXPECT_NEAR(r.metrics.at("distance_ratio_0"), 1.0, 1e-6);
}

TEST(CalibrationObjective, TrueParametersMatchPointwiseAndWithMae) {
  auto r = Eval(Input(8.8, 1.0, "pointwise"));
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_LT(r.metrics.at("error"), 1e-9);
  EXPECT_EQ(r.metrics.at("best_shift_0"), kShiftSamples);
  EXPECT_NEAR(r.metrics.at("offset_x"), kOffsetX, 1e-9);
  r = Eval(Input(8.8, 1.0, "shape", "mae"));
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_LT(r.metrics.at("error"), 1e-9);
  EXPECT_EQ(r.metrics.at("best_shift_0"), kShiftSamples);
  EXPECT_NEAR(r.metrics.at("offset_x"), kOffsetX, 1e-9);
}

TEST(CalibrationObjective, TimeOffsetGeneAlignsTheClocks) {
  objectives::EvalInput in = Input(8.8, 1.0, "shape");
  in.gene_names.push_back(kTimeOffsetParam);
  in.genes.push_back(kShiftSamples * kDt);
  const auto r = Eval(in);
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_LT(r.metrics.at("error"), 1e-9);
  EXPECT_EQ(r.metrics.at("best_shift_0"), 0);
  EXPECT_NEAR(r.metrics.at("offset_x"), kOffsetX, 1e-9);
}

TEST(CalibrationObjective, StatsModeMatchesAtTrueParameters) {
  const auto r = Eval(Input(8.8, 1.0, "stats"));
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_LT(r.metrics.at("error"), 1e-6);
  EXPECT_EQ(r.metrics.at("best_shift_0"), kShiftSamples);  // from the z shape
  const auto off = Eval(Input(10.0, 1.0, "stats"));
  ASSERT_TRUE(off.valid) << off.reason;
  EXPECT_GT(off.metrics.at("error"), 0.05);
}

// A coarse scan over the actuator force: the minimum lies at the true 8.8 N, every other
// grid point is clearly worse (the floor of numerically irrelevant changes is about 0.01 mm
// here: a 1e-4 relative change of the force gives 0.010 mm, 1e-2 gives 0.019 mm), and above
// the true value the error grows with the distance from it. Below it the gait changes
// regime (at 7.6 to 8.2 N it walks forward 1.4 mm per cycle instead of backward 0.7 mm),
// so the error there is not monotone; the stiffness scan below is.
TEST(CalibrationObjective, ForceScanHasItsMinimumAtTheTrueValue) {
  const std::vector<double> forces = {7.0, 7.6, 8.2, 8.8, 9.4, 10.0, 10.6};
  std::vector<double> errors;
  for (double f : forces) {
    const auto r = Eval(Input(f, 1.0, "shape"));
    ASSERT_TRUE(r.valid) << f << ": " << r.reason;
    errors.push_back(r.metrics.at("error"));
  }
  const size_t best = std::min_element(errors.begin(), errors.end()) - errors.begin();
  EXPECT_EQ(forces[best], 8.8) << ::testing::PrintToString(errors);
  EXPECT_LT(errors[3], 1e-9);
  for (size_t i = 0; i < forces.size(); ++i) {
    if (i != 3) {
      EXPECT_GT(errors[i], 1e-4) << forces[i];  // at least 0.1 mm
    }
  }
  for (size_t i = 3; i + 1 < forces.size(); ++i) {
    EXPECT_LT(errors[i], errors[i + 1]) << forces[i + 1];
  }
}

// The link stiffness scale: minimum at 1 and monotone on both sides.
TEST(CalibrationObjective, StiffnessScanIsMonotoneAroundTheTrueValue) {
  const std::vector<double> scales = {0.7, 0.8, 0.9, 1.0, 1.1, 1.2, 1.3};
  std::vector<double> errors;
  for (double s : scales) {
    const auto r = Eval(Input(8.8, s, "shape"));
    ASSERT_TRUE(r.valid) << s << ": " << r.reason;
    errors.push_back(r.metrics.at("error"));
  }
  SCOPED_TRACE(::testing::PrintToString(errors));
  EXPECT_LT(errors[3], 1e-9);
  for (size_t i = 0; i < 3; ++i) EXPECT_GT(errors[i], errors[i + 1]) << scales[i];
  for (size_t i = 3; i + 1 < scales.size(); ++i)
    EXPECT_LT(errors[i], errors[i + 1]) << scales[i + 1];
  EXPECT_GT(errors[2], 1e-4);
  EXPECT_GT(errors[4], 1e-4);
}

// Several recordings: the error is their mean, with metrics per recording.
TEST(CalibrationObjective, AveragesOverRecordings) {
  objectives::EvalInput in = Input(9.4, 1.0, "shape");
  auto other = std::make_shared<recording::Recording>(*MakeRecording(Defaults(), 0, 0));
  other->meta.genes = TravellingWaveGenes(0.8);  // the same gait, no offset or shift
  in.recordings.push_back(other);
  const auto r = Eval(in);
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_NEAR(r.metrics.at("error"), (r.metrics.at("error_0") + r.metrics.at("error_1")) / 2,
              1e-15);
  EXPECT_EQ(r.metrics.at("best_shift_1"), 0);
  // The same trajectory up to the offset and shift; the shift moves the window of whole
  // cycles by 3 samples, so the errors are close, not equal.
  EXPECT_NEAR(r.metrics.at("error_0"), r.metrics.at("error_1"), 0.1 * r.metrics.at("error_1"));
  EXPECT_EQ(r.metrics.count("distance_ratio_1"), 1u);
  // At the true parameters both match; offset_x is the mean of 0.02 and 0.
  in.genes[0] = 8.8;
  const auto t = Eval(in);
  ASSERT_TRUE(t.valid) << t.reason;
  EXPECT_LT(t.metrics.at("error"), 1e-9);
  EXPECT_NEAR(t.metrics.at("offset_x"), kOffsetX / 2, 1e-9);
}

// The true recording as CSV text with markers occluded: runs of 1 to 4 rows blanked (empty
// cells or NaN), about 10% of the cells, as a motion-capture export writes them. Parsed, it
// calibrates as the complete one does: the force scan keeps its minimum at the true value,
// with the same shift and offsets.
TEST(CalibrationObjective, OccludedMarkersAreBridgedAndCalibrateTheSame) {
  const recording::Recording& full = *TrueRecording();
  std::string csv = "t";
  for (const auto& c : full.channels) csv += "," + c;
  csv += "\n";
  uint64_t state = 12345;
  std::vector<int> blank_left(full.channels.size(), 0);
  for (size_t i = 0; i < full.t.size(); ++i) {
    csv += absl::StrFormat("%.6f", full.t[i]);
    for (size_t c = 0; c < full.channels.size(); ++c) {
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      if (blank_left[c] == 0 && (state >> 33) % 40 == 0) blank_left[c] = 1 + (state >> 20) % 4;
      if (blank_left[c] > 0) {
        --blank_left[c];
        csv += (state >> 40) % 2 ? "," : ",NaN";
      } else {
        csv += absl::StrFormat(",%.9g", full.columns[c][i]);
      }
    }
    csv += "\n";
  }
  std::string genes;
  for (double g : full.meta.genes)
    genes += (genes.empty() ? "" : ", ") + absl::StrFormat("%.17g", g);
  const std::string sidecar = "{\"robot\": \"caterpillar\", \"command\": {\"kind\": \"gait\", "
                              "\"genes\": [" + genes + "]}}";
  auto parsed = recording::ParseRecording(csv, sidecar, "occluded.csv", "occluded.csv.json");
  ASSERT_TRUE(parsed.ok()) << parsed.status();
  const double cells = static_cast<double>(full.t.size() * full.channels.size());
  EXPECT_GT(parsed->missing_cells, 0.05 * cells);
  EXPECT_LT(parsed->missing_cells, 0.15 * cells);
  auto occluded = std::make_shared<const recording::Recording>(*std::move(parsed));

  std::vector<double> errors;
  for (double f : {8.2, 8.8, 9.4}) {
    objectives::EvalInput in = Input(f, 1.0, "shape");
    in.recordings = {occluded};
    const auto r = Eval(in);
    ASSERT_TRUE(r.valid) << r.reason;
    errors.push_back(r.metrics.at("error"));
    if (f == 8.8) {
      EXPECT_EQ(r.metrics.at("best_shift_0"), kShiftSamples);
      EXPECT_NEAR(r.metrics.at("offset_x"), kOffsetX, 1e-5);
    }
  }
  SCOPED_TRACE(::testing::PrintToString(errors));
  // Bridging costs tens of micrometres (the hops' impacts are not straight lines; 0.040 mm
  // measured), a third of what 0.6 N of force does (0.13 and 0.37 mm).
  EXPECT_LT(errors[1], 6e-5);
  EXPECT_GT(errors[0], 1e-4);
  EXPECT_GT(errors[2], 1e-4);
  EXPECT_LT(errors[1], errors[0] / 2);
  EXPECT_LT(errors[1], errors[2] / 2);
}

TEST(CalibrationObjective, WeightsOptionWeighsTheRecordings) {
  objectives::EvalInput in = Input(9.4, 1.0, "shape");
  auto other = std::make_shared<recording::Recording>(*MakeRecording(Defaults(), 0, 0));
  other->meta.genes = TravellingWaveGenes(0.5);  // another gait: another error
  in.recordings.push_back(other);
  const auto equal = Eval(in);
  ASSERT_TRUE(equal.valid) << equal.reason;
  const double e0 = equal.metrics.at("error_0"), e1 = equal.metrics.at("error_1");
  ASSERT_GT(std::fabs(e0 - e1), 1e-6);
  in.options["weights"] = "1, 3";
  const auto weighted = Eval(in);
  ASSERT_TRUE(weighted.valid) << weighted.reason;
  EXPECT_NEAR(weighted.metrics.at("error"), (e0 + 3 * e1) / 4, 1e-15);
  EXPECT_DOUBLE_EQ(weighted.metrics.at("error_0"), e0);  // per-recording errors unweighted
  EXPECT_DOUBLE_EQ(weighted.fitness, -weighted.metrics.at("error"));
  in.options["weights"] = "0, 2";  // a zero weight leaves that recording out of the error
  EXPECT_NEAR(Eval(in).metrics.at("error"), e1, 1e-15);
  // Bad lists: the reason names the option and what it needs.
  in.options["weights"] = "1";
  auto r = Eval(in);
  EXPECT_FALSE(r.valid);
  EXPECT_NE(r.reason.find("option weights: 1 weights for 2 recordings"), std::string::npos)
      << r.reason;
  for (const char* bad : {"1,x", "1,-2", "1,inf", "0,0"}) {
    in.options["weights"] = bad;
    r = Eval(in);
    EXPECT_FALSE(r.valid) << bad;
    EXPECT_NE(r.reason.find("option weights"), std::string::npos) << bad << ": " << r.reason;
  }
}

TEST(CalibrationObjective, ChannelsOptionSelects) {
  objectives::EvalInput in = Input(9.4, 1.0, "shape");
  in.options["channels"] = "m1.z, m6.z";
  const auto r = Eval(in);
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_EQ(r.metrics.count("offset_x"), 0u);
  EXPECT_EQ(r.metrics.count("offset_z"), 1u);
  EXPECT_GT(r.metrics.at("error"), 0);
  in.options["channels"] = "m7.z";
  EXPECT_FALSE(Eval(in).valid);
}

TEST(CalibrationObjective, BadInputsAreInvalidWithAReason) {
  objectives::EvalInput in = Input(8.8, 1.0, "shape");
  in.gene_names[1] = "scale.link_stifness";
  auto r = Eval(in);
  EXPECT_FALSE(r.valid);
  EXPECT_THAT(r.reason, HasSubstr("unknown caterpillar calibration parameter"));

  in = Input(200, 1.0, "shape");
  r = Eval(in);
  EXPECT_FALSE(r.valid);
  EXPECT_THAT(r.reason, HasSubstr("outside"));

  in = Input(8.8, 1.0, "wiggle");
  EXPECT_THAT(Eval(in).reason, HasSubstr("option error"));
  in = Input(8.8, 1.0, "shape", "max");
  EXPECT_THAT(Eval(in).reason, HasSubstr("metric"));
  in = Input(8.8, 1.0, "shape");
  in.params["max_shift_samples"] = 1.5;
  EXPECT_THAT(Eval(in).reason, HasSubstr("max_shift_samples"));
  in = Input(8.8, 1.0, "shape");
  in.recordings.clear();
  EXPECT_THAT(Eval(in).reason, HasSubstr("at least one recording"));
  in = Input(8.8, 1.0, "shape");
  in.genes.pop_back();
  EXPECT_FALSE(Eval(in).valid);
}

// The unstable model of evaluation_test.cc (stiff, barely damped links at h = 2 ms).
TEST(CalibrationObjective, DivergingSimulationIsInvalid) {
  objectives::EvalInput in = Input(8.8, 1.0, "shape");
  in.gene_names = {"links.flexure.axial_stiffness_n_per_m", "links.segment.axial_stiffness_n_per_m",
                   "links.axial_damping_ratio"};
  in.genes = {1e6, 1e6, 0.01};
  in.params["timestep_ms"] = 2;
  const auto r = Eval(in);
  EXPECT_FALSE(r.valid);
  EXPECT_THAT(r.reason, HasSubstr("recording 0: simulation:"));
  EXPECT_THAT(r.reason, HasSubstr("diverged"));
}

TEST(CalibrationObjective, DeterministicAcrossThreads) {
  const objectives::EvalInput in = Input(9.4, 1.0, "shape");
  const CalibrationObjective objective(Defaults());
  objectives::EvalResult a, b;
  std::thread ta([&] { a = objective.Evaluate(in); });
  std::thread tb([&] { b = objective.Evaluate(in); });
  ta.join();
  tb.join();
  ASSERT_TRUE(a.valid && b.valid);
  EXPECT_EQ(a.fitness, b.fitness);
  EXPECT_EQ(a.metrics, b.metrics);
  EXPECT_EQ(Eval(in).fitness, a.fitness);
}

TEST(CalibrationObjective, Registers) {
  objectives::ObjectiveRegistry registry;
  RegisterCaterpillarCalibration(registry);
  EXPECT_NE(registry.Find(kCalibrationObjectiveName), nullptr);
}

}  // namespace
}  // namespace gaitforge::caterpillar
