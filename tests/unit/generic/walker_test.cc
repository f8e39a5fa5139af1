// Paper 001's walker (robots/walker/robot.yaml) on the generic builder, checked against the
// physics its paper measures: it stands level, its servo follows a step with the lag and
// speed limit it was given, a sprung joint deflects as statics says, a foot slides on an
// incline steeper than atan(mu) and holds below it (the paper's own friction test), and
// its gait travels in the paper's 5 s.
#include <cmath>
#include <string>

#include "absl/strings/str_cat.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"
#include "tests/support/robot_text.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/models/generic/generic_objective.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

const robots::RobotDescriptor& Walker() { return robots::Robot("walker"); }

class WalkerTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
  // Steps the walker with both hips commanded to `hip` for `seconds`.
  static void Hold(GenericWorld& w, double hip, double seconds) {
    const int n = static_cast<int>(std::lround(seconds / w.timestep()));
    for (int i = 0; i < n; ++i) ASSERT_TRUE(w.Step({hip, hip}).ok) << "step " << i;
  }
};

TEST_F(WalkerTest, StandsLevelOnItsSkidAndFeet) {
  ParamValues v(Walker());
  auto w = GenericWorld::Build(Walker(), v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  const auto start = (*w)->CentreOfMass();
  Hold(**w, 0, 1.0);
  const auto end = (*w)->CentreOfMass();
  EXPECT_NEAR(end[0], start[0], 1e-3);
  EXPECT_NEAR(end[2], start[2], 2e-3);  // the feet reach the ground as built
  EXPECT_LT((*w)->max_tilt(), 0.05);
  EXPECT_GE((*w)->ground_contacts(), 6);  // the skid's four corners and each foot
}

TEST_F(WalkerTest, TheServoFollowsAStepWithItsLagAndSpeedLimit) {
  ParamValues v(Walker());
  ASSERT_TRUE(v.Set("simulation.gravity_m_per_s2", 0).ok());  // no load: the servo alone
  // Lag: a small step stays below the speed limit, so the angle follows the first-order
  // lag (tau 0.04 s) behind the servo's own 1/gain = 5 ms.
  {
    auto w = GenericWorld::Build(Walker(), v, 0);
    ASSERT_TRUE(w.ok()) << w.status();
    Hold(**w, 0, 0.01);  // the lag starts from the first command
    Hold(**w, 0.1, 0.045);
    const double expected = 0.1 * (1 - std::exp(-(0.045 - 0.005) / 0.04));
    EXPECT_NEAR(*(*w)->Channel("hip_l.angle"), expected, 0.15 * expected);
    Hold(**w, 0.1, 0.4);
    EXPECT_NEAR(*(*w)->Channel("hip_l.angle"), 0.1, 0.005);
  }
  // Speed limit: without the lag a large step runs at 10.5 rad/s at most.
  ASSERT_TRUE(v.Set("servo.lag_s", 0).ok());
  auto w = GenericWorld::Build(Walker(), v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  Hold(**w, 0, 0.01);
  Hold(**w, 1.0, 0.05);
  const double angle = *(*w)->Channel("hip_l.angle");
  EXPECT_LE(angle, 10.5 * 0.05 + 1e-3);
  EXPECT_GT(angle, 0.8 * 10.5 * 0.05);
}

// The servo effects of the gap finder's catalog (workers/effects/): a further lag in series
// with the servo's own, and a deadband inside which the servo holds its joint.
TEST_F(WalkerTest, ServoEffectsLagTheStepAndStopItShortByTheDeadband) {
  ParamValues v(Walker());
  ASSERT_TRUE(v.Set("simulation.gravity_m_per_s2", 0).ok());
  ASSERT_TRUE(v.Set("servo.lag_s", 0).ok());
  auto step = [&](const ParamValues& p, double target, double seconds) {
    auto w = GenericWorld::Build(Walker(), p, 0);
    EXPECT_TRUE(w.ok()) << w.status();
    Hold(**w, 0, 0.01);
    Hold(**w, target, seconds);
    return *(*w)->Channel("hip_l.angle");
  };
  // effect.actuator_lag_s = 0.05: after one time constant (plus the servo's 5 ms) the angle
  // is at 1 - 1/e of a small step.
  ParamValues lagged = v;
  ASSERT_TRUE(lagged.Set("effect.actuator_lag_s", 0.05).ok());
  EXPECT_NEAR(step(lagged, 0.1, 0.055), 0.1 * (1 - std::exp(-1.0)), 0.012);
  EXPECT_GT(step(v, 0.1, 0.055), 0.098);  // without it, there already
  // effect.servo_deadband_rad = 0.05: the servo stops once within 0.05 rad of its command,
  // and a command inside the band does not move it at all.
  ParamValues band = v;
  ASSERT_TRUE(band.Set("effect.servo_deadband_rad", 0.05).ok());
  EXPECT_NEAR(step(band, 0.3, 0.3), 0.25, 0.006);
  EXPECT_NEAR(step(band, 0.04, 0.3), 0.0, 1e-3);
  EXPECT_THAT(std::string(band.Set("effect.servo_deadband_rad", 0.5).message()),
              ::testing::HasSubstr("outside [0, 0.2]"));
}

// A horizontal arm on a hinge out from a heavy base, its spring k (0: none) and damper c,
// and a servo of max_torque (0: limp) with a lag.
std::string Cantilever(double k, double c, double max_torque, double lag_s) {
  return absl::StrCat(R"(format: gaitforge.robot.v1
name: cantilever
summary: an arm on a sprung hinge
model: generic
parameters:
  k: {value: )", k, R"(, range: [0, 10], unit: N m/rad}
)", testing::kSimulationParameters, R"(  ground:
    mu: {value: 1, range: [0, 10]}
bodies:
  - {name: base, shape: box, size: [0.1, 0.1, 0.1], mass: 5, position: [0, 0, 0.05]}
  - {name: arm, shape: box, size: [0.1, 0.01, 0.01], mass: 0.01, position: [0.1, 0, 0.09]}
joints:
  - {name: hinge, type: hinge, bodies: [base, arm], anchor: [0.05, 0, 0.09], axis: [0, 1, 0],
     stiffness: k, damping: )", c, R"(}
actuators:
  - {name: servo, type: servo, joint: hinge, gain: 50, max_speed: 5, max_torque: )",
                      max_torque, R"(, lag_s: )", lag_s, R"(}
ground: {friction: ground.mu, erp: 0.2, cfm: 1.0e-6}
controller: {kind: sine, actuators: [servo], frequency_hz: [1, 2], amplitude_rad: [0, 1], offset_rad: [0, 1]}
sensors:
  - {kind: joint_angle, names: [hinge]}
)");
}

// The spring alone (a limp servo) holds the arm: k theta = m g (L/2) cos theta.
TEST_F(WalkerTest, ASprungJointDeflectsAsStaticsSays) {
  auto d = robots::ParseDescriptor(Cantilever(0.2, 0.002, 0, 0), "cantilever.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ParamValues v(*d);
  auto w = GenericWorld::Build(*d, v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  for (int i = 0; i < 3000; ++i) ASSERT_TRUE((*w)->Step({0.0}).ok);
  const double theta = std::fabs(*(*w)->Channel("hinge.angle"));
  // Solve k theta = m g (L/2) cos theta by fixed point.
  double expected = 0;
  for (int i = 0; i < 50; ++i) expected = 0.01 * 9.81 * 0.05 * std::cos(expected) / 0.2;
  EXPECT_NEAR(theta, expected, 0.03 * expected);
}

// A servo raising the arm slowly by 0.5 rad does the work of lifting its weight; lowering
// it, the servo brakes and gives (almost) nothing.
TEST_F(WalkerTest, ServoEnergyIsThePositiveWorkItDoes) {
  auto d = robots::ParseDescriptor(Cantilever(0, 0, 1.0, 0.3), "cantilever.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  auto energy = [&](double command) {
    ParamValues v(*d);
    auto w = GenericWorld::Build(*d, v, 0);
    EXPECT_TRUE(w.ok()) << w.status();
    for (int i = 0; i < 10; ++i) EXPECT_TRUE((*w)->Step({0.0}).ok);
    for (int i = 0; i < 3000; ++i) EXPECT_TRUE((*w)->Step({command}).ok);
    return (*w)->servo_energy();
  };
  const double up = std::max(energy(0.5), energy(-0.5));
  const double down = std::min(energy(0.5), energy(-0.5));
  const double lift = 0.01 * 9.81 * 0.05 * std::sin(0.5);  // m g (L/2) sin(0.5): 2.35 mJ
  EXPECT_NEAR(up, lift, 0.15 * lift);
  EXPECT_LT(down, 0.2 * lift);
}

// Paper 001's friction test: tilt the ground until the robot slides; tan(angle) = mu.
TEST_F(WalkerTest, ItSlidesOnAnInclineSteeperThanAtanMu) {
  auto slide = [](double slope) {
    ParamValues v(Walker());
    EXPECT_TRUE(v.Set("ground.friction_coefficient", 0.25).ok());
    EXPECT_TRUE(v.Set("effect.slope_rad", slope).ok());
    auto w = GenericWorld::Build(Walker(), v, 0);
    EXPECT_TRUE(w.ok()) << w.status();
    Hold(**w, 0, 0.2);  // settle
    const double x0 = (*w)->CentreOfMass()[0];
    Hold(**w, 0, 1.0);
    return x0 - (*w)->CentreOfMass()[0];  // downhill is -x
  };
  const double limit = std::atan(0.25);  // 0.245 rad
  EXPECT_LT(std::fabs(slide(limit - 0.04)), 1e-3);
  EXPECT_GT(slide(limit + 0.04), 0.05);
}

TEST_F(WalkerTest, ItsGaitTravelsInFiveSeconds) {
  ParamValues v(Walker());
  GaitOptions o;
  o.duration_s = v("simulation.duration_s");
  // f, amp, off, lag: near examples/walker-sweep.yaml's optimum (2.2 Hz, 60 deg peak to
  // peak, 20 deg neutral, 0.06 cycle), which crawls about 0.11 m forward in 5 s.
  const GaitResult g = EvaluateGait(Walker(), v, {2.2, 0.52, 0.35, 0.06}, o);
  ASSERT_TRUE(g.valid) << g.reason;
  EXPECT_NEAR(g.simulated_s, 5.0, 1e-9);
  EXPECT_GT(g.travel_m, 0.05);
  EXPECT_LT(g.max_tilt_rad, M_PI / 4);  // upright
  EXPECT_GE(g.torque_limited_fraction, 0.0);
  EXPECT_LE(g.torque_limited_fraction, 1.0);
}

// robot.distance on the walker: body genes reach the robot, cost of transport is work per
// weight and distance, and as the fitness it is minimised (fitness = -cost).
TEST_F(WalkerTest, TheObjectiveTakesBodyGenesAndCostOfTransport) {
  RobotDistanceObjective objective;
  objectives::EvalInput in;
  in.robot = "walker";
  in.genes = {2.2, 0.52, 0.35, 0.06, 0.31};
  in.gene_names = {"f", "amp", "off", "lag", "knee.stiffness_nm_per_rad"};
  const objectives::EvalResult travel = objective.Evaluate(in);
  ASSERT_TRUE(travel.valid) << travel.reason;
  EXPECT_EQ(travel.fitness, travel.metrics.at("travel"));
  const double cot = travel.metrics.at("cost_of_transport");
  EXPECT_NEAR(cot, travel.metrics.at("servo_energy_j") / (0.045 * 9.81 * travel.fitness), 1e-9);
  EXPECT_GT(cot, 0);
  in.options["fitness"] = "cost_of_transport";
  const objectives::EvalResult cost = objective.Evaluate(in);
  ASSERT_TRUE(cost.valid) << cost.reason;
  EXPECT_EQ(cost.fitness, -cot);
  // Another knee is another robot; a knee out of its range is a reason.
  in.genes[4] = 0.12;
  EXPECT_NE(objective.Evaluate(in).metrics.at("travel"), travel.fitness);
  in.genes[4] = 5;
  const objectives::EvalResult bad = objective.Evaluate(in);
  EXPECT_FALSE(bad.valid);
  EXPECT_NE(bad.reason.find("gene knee.stiffness_nm_per_rad"), std::string::npos) << bad.reason;
}

}  // namespace
}  // namespace gaitforge::generic
