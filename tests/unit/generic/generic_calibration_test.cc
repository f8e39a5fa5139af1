// The generic builder's effects (workers/effects: tether, slope, drag, direction-dependent
// friction, command delay) and robot.calibration on the fixture robot
// (tests/fixtures/robots/twobox/robot.yaml): each effect changes the motion, a recording
// simulated from the model matches it exactly, a changed parameter shows as error, and bad
// genes are reasons.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "absl/strings/str_join.h"
#include "robots/registry.h"
#include "services/recording/recording.h"
#include "workers/effects/effects.h"
#include "workers/models/generic/generic_calibration.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

using ::testing::HasSubstr;

std::string FixtureText() {
  std::ifstream in(std::string(GAITFORGE_SOURCE_DIR) + "/tests/fixtures/robots/twobox/robot.yaml");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const robots::RobotDescriptor& TwoBox() {
  static const auto d = *robots::ResolveRobot("twobox", FixtureText());
  return *d;
}

const std::vector<double> kGait = {2.0, 0.6, 0.2, 0.25};  // f, amp, off, phase

double Travel(const ParamValues& v) {
  GaitOptions o;
  o.measured_cycles = 4;
  const GaitResult r = EvaluateGait(TwoBox(), v, kGait, o);
  EXPECT_TRUE(r.valid) << r.reason;
  return r.distance_per_cycle_m;
}

// The channels over 4 cycles at 100 Hz.
calibration::Signals Motion(const ParamValues& v) {
  const auto run = SimulateChannels(TwoBox(), v, kGait, 4, 100);
  EXPECT_TRUE(run.valid) << run.reason;
  return run.trajectory.columns;
}

double LargestDifference(const calibration::Signals& a, const calibration::Signals& b) {
  double most = 0;
  for (size_t c = 0; c < a.size(); ++c)
    for (size_t i = 0; i < a[c].size(); ++i) most = std::max(most, std::fabs(a[c][i] - b[c][i]));
  return most;
}

class GenericCalibrationTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
};

TEST_F(GenericCalibrationTest, EveryBuilderEffectChangesTheMotionAndItsNominalIsNone) {
  ParamValues nominal(TwoBox());
  const double base = Travel(nominal);
  const calibration::Signals motion = Motion(nominal);
  int builder_effects = 0;
  for (const auto& e : effects::EffectCatalog()) {
    // Piston and spring-link effects: caterpillar_effects_test.cc; bending joints':
    // arm_effects_test.cc.
    if (e.attaches.empty() || e.attaches == "pistons" || e.attaches == "spring_links" ||
        e.attaches == "bending_joints")
      continue;
    ++builder_effects;
    ASSERT_TRUE(effects::HasPart(TwoBox(), e.attaches)) << e.id;
    ParamValues off(TwoBox()), on(TwoBox());
    for (const auto& p : e.params) {
      ASSERT_TRUE(off.Set(p.name, p.nominal).ok()) << p.name;  // 0, or a creep's no slip
      ASSERT_TRUE(on.Set(p.name, p.lo + 0.3 * (p.hi - p.lo)).ok()) << p.name;
    }
    EXPECT_EQ(Motion(off), motion) << e.id << ": the nominal must leave the model as it is, bit for bit";
    EXPECT_GT(LargestDifference(Motion(on), motion), 1e-3) << e.id << " changes nothing";
  }
  EXPECT_EQ(builder_effects, 9);
  // A tether pulls backwards: the robot travels less.
  ParamValues pulled(TwoBox());
  ASSERT_TRUE(pulled.Set("effect.tether_force_n", 0.2).ok());
  EXPECT_LT(Travel(pulled), base);
}

TEST_F(GenericCalibrationTest, ScalesEffectsAndRelationsAreCheckedWhenSet) {
  ParamValues v(TwoBox());
  ASSERT_TRUE(v.Set("scale.hinge", 2).ok());
  EXPECT_DOUBLE_EQ(v("hinge.stiffness_nm_per_rad"), 0.1);
  EXPECT_DOUBLE_EQ(v("hinge.damping_nms_per_rad"), 0.004);
  EXPECT_THAT(std::string(v.Set("scale.hinge", -1).message()), HasSubstr("positive finite factor"));
  EXPECT_THAT(std::string(v.Set("scale.hinge", 1e4).message()),
              HasSubstr("hinge.stiffness_nm_per_rad"));
  EXPECT_DOUBLE_EQ(v("hinge.stiffness_nm_per_rad"), 0.1);  // unchanged by the refusals
  EXPECT_THAT(std::string(v.Set("effect.tether_force_n", 99).message()),
              HasSubstr("effect.tether_force_n = 99 N is outside [0, 2.5]"));
  EXPECT_THAT(std::string(v.Set("effect.actuator_deadband_n", 1).message()),
              HasSubstr("twobox has no parameter effect.actuator_deadband_n"));
  EXPECT_EQ(v.Effect("effect.tether_force_n"), 0);
}

// A recording of the fixture robot simulated with `set` (NAME=VALUE pairs).
recording::Recording Simulated(const std::vector<std::pair<std::string, double>>& set,
                               double rate_hz = 100) {
  ParamValues v(TwoBox());
  for (const auto& [n, x] : set) EXPECT_TRUE(v.Set(n, x).ok()) << n;
  const auto run = SimulateChannels(TwoBox(), v, kGait, 6, rate_hz);
  EXPECT_TRUE(run.valid) << run.reason;
  std::string csv = "t";
  for (const auto& c : run.trajectory.channels) csv += "," + c;
  csv += "\n";
  for (size_t k = 0; k < run.trajectory.t.size(); ++k) {
    std::ostringstream row;
    row.precision(17);
    row << run.trajectory.t[k];
    for (const auto& col : run.trajectory.columns) row << "," << col[k];
    csv += row.str() + "\n";
  }
  const std::string side =
      R"({"robot": "twobox", "command": {"kind": "gait", "genes": [2.0, 0.6, 0.2, 0.25]}})";
  auto rec = recording::ParseRecording(csv, side, "twobox.csv", "twobox.csv.json", {}, &TwoBox());
  EXPECT_TRUE(rec.ok()) << rec.status();
  return *rec;
}

objectives::EvalResult Calibrate(const recording::Recording& rec,
                                 const std::vector<std::pair<std::string, double>>& genes,
                                 const std::string& error = "shape") {
  objectives::EvalInput in;
  in.robot = "twobox";
  in.robot_descriptor = FixtureText();
  for (const auto& [n, x] : genes) {
    in.gene_names.push_back(n);
    in.genes.push_back(x);
  }
  in.lo.assign(in.genes.size(), -1e9);
  in.hi.assign(in.genes.size(), 1e9);
  in.options["error"] = error;
  in.recordings.push_back(std::make_shared<const recording::Recording>(rec));
  return RobotCalibrationObjective().Evaluate(in);
}

TEST_F(GenericCalibrationTest, TheModelMatchesItsOwnRecordingAndAChangeShowsAsError) {
  const recording::Recording rec = Simulated({{"effect.tether_force_n", 0.15}});
  ASSERT_EQ(rec.channels, TwoBox().Channels());
  for (const std::string error : {"shape", "pointwise"}) {
    const auto same = Calibrate(rec, {{"effect.tether_force_n", 0.15}}, error);
    ASSERT_TRUE(same.valid) << same.reason;
    EXPECT_LT(same.metrics.at("error"), 1e-9) << error;
    const auto without = Calibrate(rec, {{"effect.tether_force_n", 0}}, error);
    ASSERT_TRUE(without.valid) << without.reason;
    EXPECT_GT(without.metrics.at("error"), 1e-4) << error;
    // The recorded robot, held back by its tether, moves less far along +x.
    EXPECT_LT(without.metrics.at("real_distance_per_cycle_0"),
              without.metrics.at("sim_distance_per_cycle_0"));
  }
}

TEST_F(GenericCalibrationTest, BadGenesAndRecordingsAreReasons) {
  const recording::Recording rec = Simulated({});
  EXPECT_THAT(Calibrate(rec, {{"rear.mass_kg", 5}}).reason,
              HasSubstr("gene 0: rear.mass_kg = 5 kg is outside [0.01, 2] kg"));
  EXPECT_THAT(Calibrate(rec, {{"effect.spring_softening", 1}}).reason,
              HasSubstr("twobox has no parameter effect.spring_softening"));
  recording::Recording other = rec;
  other.meta.robot = "caterpillar";
  EXPECT_THAT(Calibrate(other, {}).reason, HasSubstr("a recording of robot 'caterpillar'"));
  // Without the descriptor the recording's robot is unknown, named as such.
  std::string csv = "t,hinge.angle\n0,0\n0.01,0\n";
  auto unknown = recording::ParseRecording(
      csv, R"({"robot": "twobox", "command": {"kind": "gait", "genes": [2, 0.6, 0.2, 0.25]}})",
      "a.csv", "a.csv.json");
  EXPECT_THAT(std::string(unknown.status().message()),
              HasSubstr("unknown robot 'twobox' (built in: " + absl::StrJoin(robots::RobotNames(), ", ") +
                        "; another robot's recording needs its descriptor)"));
  auto bad_channel = recording::ParseRecording(
      "t,elbow.angle\n0,0\n0.01,0\n",
      R"({"robot": "twobox", "command": {"kind": "gait", "genes": [2, 0.6, 0.2, 0.25]}})",
      "b.csv", "b.csv.json", {}, &TwoBox());
  EXPECT_THAT(std::string(bad_channel.status().message()), HasSubstr("elbow.angle"));
}

TEST_F(GenericCalibrationTest, EffectsApplyWhereTheRobotHasTheirParts) {
  const auto& cat = robots::Robot("caterpillar");
  for (const auto& e : effects::EffectCatalog())
    if (!e.params.empty() && e.attaches != "servos" && e.attaches != "bending_joints") {
      EXPECT_EQ(effects::WhyNotApplicable(e, cat), "") << e.id;
    }
  EXPECT_THAT(effects::WhyNotApplicable(*effects::FindEffect("servo.deadband"), cat),
              HasSubstr("it attaches to servos, which caterpillar lacks"));
  EXPECT_THAT(effects::WhyNotApplicable(*effects::FindEffect("actuator.deadband"), robots::Robot("walker")),
              HasSubstr("it attaches to pistons, which walker lacks"));
  EXPECT_EQ(effects::WhyNotApplicable(*effects::FindEffect("servo.deadband"), robots::Robot("walker")), "");
  EXPECT_EQ(effects::WhyNotApplicable(*effects::FindEffect("tether.constant"), TwoBox()), "");
  EXPECT_THAT(effects::WhyNotApplicable(*effects::FindEffect("mass.offset"), TwoBox()),
              HasSubstr("twobox has no calibratable scale.mass"));
  const auto names = effects::FittableNames(TwoBox());
  EXPECT_THAT(names, ::testing::Contains("effect.tether_force_n"));
  EXPECT_THAT(names, ::testing::Contains("scale.hinge"));
  EXPECT_THAT(names, ::testing::Not(::testing::Contains("effect.spring_softening")));
}

}  // namespace
}  // namespace gaitforge::generic
