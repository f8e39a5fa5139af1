// The caterpillar's calibration on the generic build: its calibratable parameters and
// scales (ParamValues on its descriptor), and a round trip of robot.calibration on a
// recording made in memory from the robot with known parameters, a constant offset on every
// x channel and a time shift.
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "absl/strings/str_format.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "robots/onoff_waves.h"
#include "robots/registry.h"
#include "services/recording/recording.h"
#include "workers/models/generic/generic_calibration.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/objectives/recording_comparison.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

using ::testing::HasSubstr;

const robots::RobotDescriptor& Caterpillar() { return robots::Robot("caterpillar"); }

// ---------------------------------------------------------------------------------------
// Parameters and scales

TEST(CaterpillarCalibrationParams, SetsAbsoluteFields) {
  ParamValues v(Caterpillar());
  ASSERT_TRUE(v.Set("actuators.force_n", 7.5).ok());
  EXPECT_EQ(v("actuators.force_n"), 7.5);
  ASSERT_TRUE(v.Set("lumps.mass_kg", 0.04).ok());
  EXPECT_EQ(v("lumps.mass_kg"), 0.04);
  ASSERT_TRUE(v.Set("ground.contact_cfm", 2e-5).ok());
  EXPECT_EQ(v("ground.contact_cfm"), 2e-5);
  ASSERT_TRUE(std::isinf(v("ground.friction_coefficient")));
  ASSERT_TRUE(v.Set("ground.friction_coefficient", 0.6).ok());
  EXPECT_EQ(v("ground.friction_coefficient"), 0.6);
}

TEST(CaterpillarCalibrationParams, ScalesMultiplyGroups) {
  const ParamValues d(Caterpillar());
  ParamValues v(Caterpillar());
  const std::string fa = "links.flexure.axial_stiffness_n_per_m",
                    fb = "links.flexure.bending_stiffness_nm_per_rad",
                    sa = "links.segment.axial_stiffness_n_per_m",
                    sb = "links.segment.bending_stiffness_nm_per_rad";
  ASSERT_TRUE(v.Set("scale.link_stiffness", 2.0).ok());
  for (const auto& n : {fa, fb, sa, sb}) EXPECT_EQ(v(n), 2 * d(n)) << n;
  ASSERT_TRUE(v.Set("scale.bending_stiffness", 0.5).ok());  // applied on top
  EXPECT_EQ(v(fb), d(fb));
  EXPECT_EQ(v(fa), 2 * d(fa));
  ASSERT_TRUE(v.Set("scale.axial_stiffness", 0.5).ok());
  EXPECT_EQ(v(sa), d(sa));
  ASSERT_TRUE(v.Set("scale.mass", 1.5).ok());
  EXPECT_DOUBLE_EQ(v("lumps.mass_kg"), 1.5 * d("lumps.mass_kg"));
}

TEST(CaterpillarCalibrationParams, RejectsOutOfRangeUnknownAndRelations) {
  ParamValues v(Caterpillar());
  absl::Status s = v.Set("actuators.force_n", 120);
  EXPECT_FALSE(s.ok());
  EXPECT_THAT(std::string(s.message()), HasSubstr("actuators.force_n = 120 N is outside [0, 100] N"));
  EXPECT_FALSE(v.Set("links.axial_damping_ratio", NAN).ok());
  EXPECT_FALSE(v.Set("scale.mass", 0).ok());
  EXPECT_FALSE(v.Set("scale.mass", -1).ok());
  // 1040 N/m * 1e4 leaves [1, 1e6]; nothing changes.
  s = v.Set("scale.link_stiffness", 1e4);
  EXPECT_FALSE(s.ok());
  EXPECT_THAT(std::string(s.message()), HasSubstr("links.flexure.axial_stiffness_n_per_m"));
  EXPECT_EQ(v("links.flexure.axial_stiffness_n_per_m"), 1040);
  // The stroke stop below the rest length.
  s = v.Set("actuators.max_length_m", 0.04);
  EXPECT_FALSE(s.ok());
  EXPECT_THAT(std::string(s.message()),
              HasSubstr("relation 'actuators.max_length_m > actuators.min_length_m' fails"));
  EXPECT_EQ(v("actuators.max_length_m"), 0.062);
  s = v.Set("actuators.forse_n", 1);
  EXPECT_EQ(s.code(), absl::StatusCode::kNotFound);
  EXPECT_THAT(std::string(s.message()), HasSubstr("nearest: actuators.force_n"));
}

TEST(CaterpillarCalibrationParams, EveryCalibratableNameIsSettable) {
  for (const std::string& name : Caterpillar().CalibratableNames()) {
    ParamValues v(Caterpillar());
    const double x = name.rfind("scale.", 0) == 0                        ? 1.1
                     : name == "actuators.max_length_m"                  ? 0.06
                     : name == "ground.contact_cfm"                      ? 1e-4
                     : name.rfind("effect.", 0) == 0                     ? 0.1
                     : name == "simulation.timestep_s"                   ? 5e-4
                     : name.find("axial_stiffness") != std::string::npos ? 500
                                                                         : 0.5;
    const absl::Status s = v.Set(name, x);
    EXPECT_TRUE(s.ok()) << name << ": " << s;
  }
}

// The objective: a round trip on a simulated recording

constexpr double kPeriod = 0.8;
constexpr double kDt = 0.01;       // 100 Hz
constexpr int kCycles = 12;        // recorded cycles after 2 settle cycles
constexpr double kOffsetX = 0.02;  // added to every m*.x channel (m)
constexpr int kShiftSamples = 3;   // the recording's clock runs 3 samples behind

std::vector<double> Wave(double period) { return robots::WaveGenes(6, period, {}); }
std::vector<double> Genes() { return Wave(kPeriod); }

// A recording of the robot with `v`, made like gaitforge-sim trajectory: markers over the
// measured cycles after 2 settle cycles, t absolute from rest; then x_offset added to every
// x channel and t reduced by time_shift.
std::shared_ptr<const recording::Recording> MakeRecording(const ParamValues& v, double x_offset,
                                                          double time_shift) {
  sim::InitThread();
  const calibration::SimRun run = SimulateChannels(Caterpillar(), v, Genes(), kCycles, 1 / kDt, 0, {}, 2);
  EXPECT_TRUE(run.valid) << run.reason;
  auto rec = std::make_shared<recording::Recording>();
  rec->meta.robot = "caterpillar";
  rec->meta.command_kind = "gait";
  rec->meta.genes = Genes();
  rec->meta.source = "simulation";
  rec->dt = kDt;
  for (double t : run.trajectory.t) rec->t.push_back(t - time_shift);
  for (size_t c = 0; c < run.trajectory.channels.size(); ++c) {
    const std::string& name = run.trajectory.channels[c];
    std::vector<double> col = run.trajectory.columns[c];
    if (name.size() > 2 && name.substr(name.size() - 2) == ".x")
      for (double& x : col) x += x_offset;
    rec->channels.push_back(name);
    rec->columns.push_back(std::move(col));
  }
  return rec;
}

ParamValues Defaults() { return ParamValues(Caterpillar()); }

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
  in.robot = "caterpillar";
  return in;
}

objectives::EvalResult Eval(const objectives::EvalInput& in) {
  return RobotCalibrationObjective().Evaluate(in);
}

TEST(CaterpillarCalibration, RecordingMovesAndTrueParametersMatchInShape) {
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

TEST(CaterpillarCalibration, TrueParametersMatchPointwiseAndWithMae) {
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

TEST(CaterpillarCalibration, TimeOffsetGeneAlignsTheClocks) {
  objectives::EvalInput in = Input(8.8, 1.0, "shape");
  in.gene_names.push_back(calibration::kTimeOffsetGene);
  in.genes.push_back(kShiftSamples * kDt);
  const auto r = Eval(in);
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_LT(r.metrics.at("error"), 1e-9);
  EXPECT_EQ(r.metrics.at("best_shift_0"), 0);
  EXPECT_NEAR(r.metrics.at("offset_x"), kOffsetX, 1e-9);
}

// With noise on every marker, the compared cycles (shape) and samples (pointwise) are the
// recording's own: moving the time offset gene by whole samples, which the shift search
// undoes exactly, must leave the error as it is. Were the cycles placed by the offset, one
// offset would average one cycle more and win the noise that removes.
TEST(CaterpillarCalibration, ComparedCyclesDoNotDependOnTheTimeOffset) {
  auto noisy = std::make_shared<recording::Recording>(*TrueRecording());
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1e-3);
  for (auto& col : noisy->columns)
    for (double& x : col) x += noise(rng);
  for (const std::string error : {"shape", "pointwise"}) {
    std::vector<double> errors;
    for (int k = -3; k <= 3; ++k) {
      objectives::EvalInput in = Input(8.8, 1.0, error);
      in.recordings = {noisy};
      in.gene_names.push_back(calibration::kTimeOffsetGene);
      in.genes.push_back(k * kDt);
      const auto r = Eval(in);
      ASSERT_TRUE(r.valid) << r.reason;
      EXPECT_EQ(r.metrics.at("best_shift_0"), kShiftSamples - k) << error << " offset " << k;
      errors.push_back(r.metrics.at("error"));
    }
    EXPECT_GT(errors[0], 1e-4) << error;  // the noise shows
    for (double e : errors) EXPECT_NEAR(e, errors[0], 1e-9 * errors[0]) << error;
  }
}

// A clock offset that is not a whole number of samples (a real recording's) is profiled out
// like a whole one: the shift is found to a fraction of a sample, and the error is the same
// wherever the time offset gene puts the clock within a sample. On the bins' grid alone a
// fast signal misaligned by part of a sample reads as a large error, and a fit would have to
// find the offset to a fraction of a sample.
TEST(CaterpillarCalibration, ASubSampleClockOffsetIsProfiledOut) {
  const double shift = (kShiftSamples + 0.37) * kDt;
  static const auto rec = MakeRecording(Defaults(), kOffsetX, shift);
  for (const std::string error : {"shape", "pointwise"}) {
    std::vector<double> errors;
    for (double fraction : {0.0, 0.2, 0.45}) {
      objectives::EvalInput in = Input(8.8, 1.0, error);
      in.recordings = {rec};
      in.gene_names.push_back(calibration::kTimeOffsetGene);
      in.genes.push_back(fraction * kDt);
      const auto r = Eval(in);
      ASSERT_TRUE(r.valid) << r.reason;
      EXPECT_NEAR(r.metrics.at("time_shift_s_0") + fraction * kDt, shift, 0.02 * kDt)
          << error << " gene at " << fraction << " of a sample";
      errors.push_back(r.metrics.at("error"));
    }
    // Only the interpolation of the simulation between its samples is left (under 1 um).
    for (double e : errors) EXPECT_LT(e, 1e-6) << error;
  }
  // The same force off its value still reads as an error far above that.
  const auto off = Eval([&] {
    objectives::EvalInput in = Input(10.0, 1.0, "shape");
    in.recordings = {rec};
    return in;
  }());
  ASSERT_TRUE(off.valid) << off.reason;
  EXPECT_GT(off.metrics.at("error"), 1e-4);
}

TEST(CaterpillarCalibration, StatsModeMatchesAtTrueParameters) {
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
TEST(CaterpillarCalibration, ForceScanHasItsMinimumAtTheTrueValue) {
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
TEST(CaterpillarCalibration, StiffnessScanIsMonotoneAroundTheTrueValue) {
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
TEST(CaterpillarCalibration, AveragesOverRecordings) {
  objectives::EvalInput in = Input(9.4, 1.0, "shape");
  auto other = std::make_shared<recording::Recording>(*MakeRecording(Defaults(), 0, 0));
  other->meta.genes = Wave(0.8);  // the same gait, no offset or shift
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
TEST(CaterpillarCalibration, OccludedMarkersAreBridgedAndCalibrateTheSame) {
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

TEST(CaterpillarCalibration, WeightsOptionWeighsTheRecordings) {
  objectives::EvalInput in = Input(9.4, 1.0, "shape");
  auto other = std::make_shared<recording::Recording>(*MakeRecording(Defaults(), 0, 0));
  other->meta.genes = Wave(0.5);  // another gait: another error
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

TEST(CaterpillarCalibration, ChannelsOptionSelects) {
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

TEST(CaterpillarCalibration, BadInputsAreInvalidWithAReason) {
  objectives::EvalInput in = Input(8.8, 1.0, "shape");
  in.gene_names[1] = "scale.link_stifness";
  auto r = Eval(in);
  EXPECT_FALSE(r.valid);
  EXPECT_THAT(r.reason, HasSubstr("caterpillar has no parameter scale.link_stifness"));

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
TEST(CaterpillarCalibration, DivergingSimulationIsInvalid) {
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

TEST(CaterpillarCalibration, DeterministicAcrossThreads) {
  const objectives::EvalInput in = Input(9.4, 1.0, "shape");
  const RobotCalibrationObjective objective;
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

}  // namespace
}  // namespace gaitforge::generic
