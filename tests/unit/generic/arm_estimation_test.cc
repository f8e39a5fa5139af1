// Paper 004's estimation on the continuum arm (robots/continuum_arm/robot.yaml): a playback
// recording's rod forces drive the model (generic_playback.h), robot.calibration's
// acceleration error (error = acceleration) compares the tip's accelerations, and the
// error is zero at the parameters that made the recording and grows away from them, along
// each of P = [k_x, k_y, c_x, c_y]. Bad input is refused with the reason.
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_calibration.h"
#include "workers/models/generic/generic_playback.h"
#include "workers/models/generic/generic_world.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

const robots::RobotDescriptor& Arm() { return robots::Robot("continuum_arm"); }

const std::vector<std::string> kP = {"joint.stiffness_x_nm_per_rad", "joint.stiffness_y_nm_per_rad",
                                     "joint.damping_x_nms_per_rad", "joint.damping_y_nms_per_rad"};
const std::vector<double> kTruth = {0.15, 0.08, 0.03, 0.015};

// Rod forces f(t) at 1 kHz for `seconds` as a playback recording's input columns.
recording::Recording Inputs(double seconds, const std::vector<double>& f, double swing_hz = 0) {
  recording::Recording r;
  r.meta.robot = "continuum_arm";
  r.meta.command_kind = "playback";
  r.channels = {"rod1.force", "rod2.force", "rod3.force"};
  r.columns.resize(3);
  r.dt = 1e-3;
  for (int k = 0; k <= std::lround(seconds * 1000); ++k) {
    const double t = k * 1e-3;
    r.t.push_back(t);
    for (int i = 0; i < 3; ++i)
      r.columns[i].push_back(swing_hz > 0 ? f[i] * std::sin(2 * M_PI * swing_hz * t + 2.1 * i) : f[i]);
  }
  return r;
}

// The arm with P = p driven by `inputs`, recorded at 100 Hz: its channels and the inputs.
std::shared_ptr<const recording::Recording> Record(const recording::Recording& inputs,
                                                   const std::vector<double>& p) {
  ParamValues v(Arm());
  for (size_t i = 0; i < kP.size(); ++i) EXPECT_TRUE(v.Set(kP[i], p[i]).ok());
  const auto run = SimulatePlayback(Arm(), v, inputs, 0, inputs.t.back(), 100);
  EXPECT_TRUE(run.valid) << run.reason;
  auto rec = std::make_shared<recording::Recording>();
  rec->meta = inputs.meta;
  rec->t = run.trajectory.t;
  rec->channels = run.trajectory.channels;
  rec->columns = run.trajectory.columns;
  rec->dt = 0.01;
  for (size_t c = 0; c < inputs.channels.size(); ++c) {
    rec->channels.push_back(inputs.channels[c]);
    rec->columns.emplace_back();
    for (double t : rec->t) rec->columns.back().push_back(calibration::Interpolate(inputs.t, inputs.columns[c], t));
  }
  return rec;
}

objectives::EvalResult Fit(const std::vector<std::shared_ptr<const recording::Recording>>& recs,
                           const std::vector<double>& p, double window_s = 0.2,
                           const std::string& error = "acceleration") {
  objectives::EvalInput in;
  in.robot = "continuum_arm";
  in.gene_names = kP;
  in.genes = p;
  in.options = {{"error", error}, {"metric", "mae"}, {"channels", "tip.x,tip.y,tip.z"}};
  in.params = {{"max_shift_samples", 0}, {"window_s", window_s}};
  in.recordings = recs;
  return RobotCalibrationObjective().Evaluate(in);
}

class ArmEstimationTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
};

TEST_F(ArmEstimationTest, PlaybackIsTheForcesAppliedStepByStep) {
  const std::vector<double> f = {0.3025, 0.3263, -0.1265};  // the paper's Table 2 state
  const auto rec = Record(Inputs(0.3, f), kTruth);
  ParamValues v(Arm());
  for (size_t i = 0; i < kP.size(); ++i) ASSERT_TRUE(v.Set(kP[i], kTruth[i]).ok());
  auto w = GenericWorld::Build(Arm(), v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  for (int i = 0; i < 300; ++i) ASSERT_TRUE((*w)->Step(f).ok);
  const int x = rec->ChannelIndex("tip.x");
  EXPECT_DOUBLE_EQ(rec->columns[x].back(), *(*w)->Channel("tip.x"));
  EXPECT_GT(std::fabs(rec->columns[x].back()), 1e-3);  // it moved
}

TEST_F(ArmEstimationTest, ErrorIsZeroAtTheTruthAndGrowsAlongEveryParameter) {
  const std::vector<std::shared_ptr<const recording::Recording>> recs = {
      Record(Inputs(0.5, {0.3025, 0.3263, -0.1265}), kTruth),
      Record(Inputs(0.5, {-0.2, 0.1, 0.4}), kTruth)};
  const auto at_truth = Fit(recs, kTruth);
  ASSERT_TRUE(at_truth.valid) << at_truth.reason;
  EXPECT_LT(at_truth.metrics.at("error"), 1e-6);
  EXPECT_NEAR(at_truth.metrics.at("acceleration_fitness"), 1, 1e-6);
  for (size_t i = 0; i < kP.size(); ++i) {
    double last = at_truth.metrics.at("error");
    for (double scale : {1.05, 1.2, 1.5}) {
      std::vector<double> p = kTruth;
      p[i] *= scale;
      const auto r = Fit(recs, p);
      ASSERT_TRUE(r.valid) << r.reason;
      EXPECT_GT(r.metrics.at("error"), last) << kP[i] << " x " << scale;
      last = r.metrics.at("error");
    }
    EXPECT_GT(last, 0.02) << kP[i];  // half as much again is seen
  }
}

TEST_F(ArmEstimationTest, TheWindowLimitsTheComparisonAndTheRun) {
  const std::vector<std::shared_ptr<const recording::Recording>> recs = {
      Record(Inputs(1.0, {0.3, 0.3, -0.1}, 1.3), kTruth)};
  std::vector<double> p = kTruth;
  p[0] *= 1.3;
  const auto short_window = Fit(recs, p, 0.2), whole = Fit(recs, p, 0);
  ASSERT_TRUE(short_window.valid && whole.valid);
  EXPECT_NE(short_window.metrics.at("error"), whole.metrics.at("error"));
  EXPECT_LT(short_window.metrics.at("simulated_s"), 0.3);
  EXPECT_GT(whole.metrics.at("simulated_s"), 1.0);
}

TEST_F(ArmEstimationTest, RefusesWhatItCannotCompare) {
  auto rec = std::make_shared<recording::Recording>(*Record(Inputs(0.3, {0.3, 0.3, -0.1}), kTruth));
  const auto shape = Fit({rec}, kTruth, 0.2, "shape");
  EXPECT_FALSE(shape.valid);
  EXPECT_NE(shape.reason.find("a playback) compares with error = pointwise or acceleration"),
            std::string::npos) << shape.reason;
  const auto tiny = Fit({rec}, kTruth, 0.03);  // 4 samples: none with the filter's 9
  EXPECT_FALSE(tiny.valid);
  EXPECT_NE(tiny.reason.find("window_s = 0.03 s at 0.01 s intervals holds none"), std::string::npos)
      << tiny.reason;
  // Without a rod's column the model cannot be driven.
  auto no_rod = std::make_shared<recording::Recording>(*rec);
  const int rod = no_rod->ChannelIndex("rod2.force");
  no_rod->channels.erase(no_rod->channels.begin() + rod);
  no_rod->columns.erase(no_rod->columns.begin() + rod);
  const auto undriven = Fit({no_rod}, kTruth);
  EXPECT_FALSE(undriven.valid);
  EXPECT_NE(undriven.reason.find("no column rod2.force to drive rod2"), std::string::npos)
      << undriven.reason;
  // Without the tip, nothing the option channels names.
  auto no_tip = std::make_shared<recording::Recording>(*rec);
  no_tip->channels[no_tip->ChannelIndex("tip.x")] = "j1.angle1x";
  const auto blind = Fit({no_tip}, kTruth);
  EXPECT_FALSE(blind.valid);
  EXPECT_NE(blind.reason.find("no channel tip.x (option channels)"), std::string::npos) << blind.reason;
}

}  // namespace
}  // namespace gaitforge::generic
