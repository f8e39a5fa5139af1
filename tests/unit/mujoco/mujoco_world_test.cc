// The MuJoCo build of robots on the generic builder (workers/models/mujoco/): it puts every
// body and joint where the descriptor does, its hinge angles agree with the ODE build's in
// sign and size, its servo follows a command, bad structure is refused with the reason, and
// a gait runs through it.
#include <cmath>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"
#include "tests/support/fixture_robot.h"
#include "tests/support/robot_text.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/models/mujoco/mjcf.h"
#include "workers/models/mujoco/mujoco_world.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::mujoco {
namespace {

using ::testing::HasSubstr;

double Eval(const robots::Expr& e, const generic::ParamValues& v) {
  return e.Eval([&v](const std::string& n) { return v(n); });
}

TEST(MujocoWorld, BodiesAndAnchorsStartWhereTheDescriptorPutsThem) {
  for (const std::string name : {"walker", "tigrillo"}) {
    const robots::RobotDescriptor& d = robots::Robot(name);
    generic::ParamValues v(d);
    auto w = MujocoWorld::Build(d, v, 0);
    ASSERT_TRUE(w.ok()) << name << ": " << w.status();
    for (size_t i = 0; i < d.bodies.size(); ++i) {
      const auto p = (*w)->BodyPosition(static_cast<int>(i));
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(p[k], Eval(d.bodies[i].position[k], v), 1e-9) << name << " " << d.bodies[i].name;
    }
    for (size_t j = 0; j < d.joints.size(); ++j) {
      if (d.joints[j].type != "hinge") continue;
      const auto a = (*w)->JointAnchor(static_cast<int>(j));
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(a[k], Eval(d.joints[j].anchor[k], v), 1e-9) << name << " " << d.joints[j].name;
    }
  }
}

// Spheres (tests/fixtures/robots/balls): on a slope the ball with friction rolls (5/7 g sin s)
// and the frictionless one slides (g sin s), as on the ODE build (sphere_test.cc).
TEST(MujocoWorld, SpheresRollAndSlideAsOnTheOdeBuild) {
  const robots::RobotDescriptor& d = testing::FixtureRobot("balls");
  generic::ParamValues v(d);
  const double s = 0.1, t = 0.5;
  ASSERT_TRUE(v.Set("effect.slope_rad", s).ok());
  auto w = MujocoWorld::Build(d, v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  const int steps = static_cast<int>(std::lround(t / (*w)->timestep()));
  for (int i = 0; i < steps; ++i) ASSERT_TRUE((*w)->Step({}).ok);
  const double slide = 0.5 * v("simulation.gravity_m_per_s2") * std::sin(s) * t * t;
  EXPECT_NEAR(-*(*w)->Channel("sliding_c.x"), slide, 0.02 * slide);
  EXPECT_NEAR(-*(*w)->Channel("rolling_c.x"), 5.0 / 7.0 * slide, 0.02 * slide);
}

// A hinge's stops are radians in the descriptor, and MJCF reads angles in degrees unless
// told otherwise: the build must keep them radians (a servo reaches 0.8 rad inside stops of
// +-1 rad, and stops at 1 rad when sent past it; a 1 kg arm, as MuJoCo's stops are soft
// in proportion to what they hold).
TEST(MujocoWorld, JointStopsAreRadiansAsInTheDescriptor) {
  const std::string text = std::string(R"(format: gaitforge.robot.v1
name: stopped
model: generic
parameters:
)") + testing::kSimulationParameters + R"(bodies:
  - {name: base, shape: box, size: [0.1, 0.1, 0.1], mass: 5, position: [0, 0, 0.05]}
  - {name: arm, shape: box, size: [0.1, 0.01, 0.01], mass: 1, position: [0.1, 0, 0.09]}
joints:
  - {name: hinge, type: hinge, bodies: [base, arm], anchor: [0.05, 0, 0.09], axis: [0, 0, 1], lo: -1, hi: 1}
actuators:
  - {name: servo, type: servo, joint: hinge, gain: 50, max_speed: 5, max_torque: 1, lag_s: 0}
ground: {friction: 1, erp: 0.2, cfm: 1.0e-6}
controller: {kind: sine, actuators: [servo], frequency_hz: [1, 2], amplitude_rad: [0, 1], offset_rad: [0, 1]}
sensors:
  - {kind: joint_angle, names: [hinge]}
)";
  auto d = robots::ParseDescriptor(text, "stopped.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  generic::ParamValues v(*d);
  auto w = MujocoWorld::Build(*d, v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE((*w)->Step({0.8}).ok);
  EXPECT_NEAR(*(*w)->Channel("hinge.angle"), 0.8, 0.02);
  for (int i = 0; i < 1000; ++i) ASSERT_TRUE((*w)->Step({1.5}).ok);
  EXPECT_NEAR(*(*w)->Channel("hinge.angle"), 1.0, 0.03);
}

// An arm on a sprung hinge out from a heavy base, and a servo-driven second arm.
const std::string kArms = std::string(R"(format: gaitforge.robot.v1
name: arms
model: generic
parameters:
)") + testing::kSimulationParameters + R"(bodies:
  - {name: base, shape: box, size: [0.1, 0.1, 0.1], mass: 5, position: [0, 0, 0.05]}
  - {name: arm, shape: box, size: [0.1, 0.01, 0.01], mass: 0.01, position: [0.1, 0, 0.09]}
  - {name: arm2, shape: box, size: [0.1, 0.01, 0.01], mass: 0.01, position: [-0.1, 0, 0.09]}
joints:
  - {name: hinge, type: hinge, bodies: [base, arm], anchor: [0.05, 0, 0.09], axis: [0, 1, 0],
     stiffness: 0.05, damping: 0.001}
  - {name: hinge2, type: hinge, bodies: [base, arm2], anchor: [-0.05, 0, 0.09], axis: [0, 1, 0],
     damping: 0.001}
actuators:
  - {name: servo, type: servo, joint: hinge2, gain: 50, max_speed: 5, max_torque: 1, lag_s: 0}
ground: {friction: 1, erp: 0.2, cfm: 1.0e-6}
controller: {kind: sine, actuators: [servo], frequency_hz: [1, 2], amplitude_rad: [0, 1], offset_rad: [0, 1]}
sensors:
  - {kind: joint_angle, names: [hinge, hinge2]}
  - {kind: marker, names: [tip], axes: [x, z], bodies: [arm], offset: [0.05, 0, 0]}
)";

TEST(MujocoWorld, HingeAnglesAndMarkersAgreeWithTheOdeBuild) {
  auto d = robots::ParseDescriptor(kArms, "arms.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  generic::ParamValues v(*d);
  sim::InitThread();
  // Held at 0.3 rad by the servo, the sprung arm sagging under gravity (about -0.098 rad).
  const auto ode = generic::SimulateChannels(*d, v, {1, 0, 0.3, 0}, 1, 10);
  const auto mj = generic::SimulateChannels(*d, v, {1, 0, 0.3, 0}, 1, 10, 0, Engine());
  ASSERT_TRUE(ode.valid && mj.valid) << ode.reason << mj.reason;
  const auto& a = ode.trajectory.columns;
  const auto& b = mj.trajectory.columns;
  EXPECT_LT(a[0].back(), -0.05);  // sags: the sign convention is the ODE build's
  EXPECT_NEAR(b[0].back(), a[0].back(), 1e-3);
  EXPECT_NEAR(b[1].back(), 0.3, 1e-3);
  for (size_t c = 2; c < a.size(); ++c) EXPECT_NEAR(b[c].back(), a[c].back(), 1e-3);
}

TEST(MujocoWorld, ALoopOrAnUnsupportedEffectIsRefusedWithTheReason) {
  std::string text = kArms;
  text.replace(text.find("bodies: [base, arm2]"), 20, "bodies: [arm2, arm]");
  auto d = robots::ParseDescriptor(text, "arms.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  generic::ParamValues v(*d);
  EXPECT_THAT(std::string(ToMjcf(*d, v, 0).status().message()),
              HasSubstr("body arm is the second body of two joints; a MuJoCo build needs a tree"));
  const robots::RobotDescriptor& walker = robots::Robot("walker");
  generic::ParamValues slip(walker);
  ASSERT_TRUE(slip.Set("effect.friction_backward", 0.5).ok());
  EXPECT_THAT(std::string(MujocoWorld::Build(walker, slip, 0).status().message()),
              HasSubstr("no direction-dependent friction"));
  generic::ParamValues creep(walker);
  ASSERT_TRUE(creep.Set("effect.contact_slip_m_per_n_s", 0.01).ok());
  EXPECT_THAT(std::string(MujocoWorld::Build(walker, creep, 0).status().message()),
              HasSubstr("no creeping contact"));
}

// Paper 001's incline test on the MuJoCo build: the resting walker holds on a slope below
// atan(mu) and slides on one above it (MuJoCo's soft contact creeps a little below).
TEST(MujocoWorld, TheWalkerSlidesOnAnInclineSteeperThanAtanMu) {
  const robots::RobotDescriptor& d = robots::Robot("walker");
  auto slide = [&d](double slope) {
    generic::ParamValues v(d);
    EXPECT_TRUE(v.Set("ground.friction_coefficient", 0.25).ok());
    EXPECT_TRUE(v.Set("effect.slope_rad", slope).ok());
    auto w = MujocoWorld::Build(d, v, 0);
    EXPECT_TRUE(w.ok()) << w.status();
    for (int i = 0; i < 200; ++i) EXPECT_TRUE((*w)->Step({0, 0}).ok);
    const double x0 = (*w)->CentreOfMass()[0];
    for (int i = 0; i < 1000; ++i) EXPECT_TRUE((*w)->Step({0, 0}).ok);
    return x0 - (*w)->CentreOfMass()[0];
  };
  const double limit = std::atan(0.25);
  EXPECT_LT(std::fabs(slide(limit - 0.04)), 2e-3);
  EXPECT_GT(slide(limit + 0.04), 0.05);
}

TEST(MujocoWorld, AGaitRunsAndIsDeterministic) {
  const robots::RobotDescriptor& d = robots::Robot("walker");
  generic::ParamValues v(d);
  generic::GaitOptions o;
  o.engine = Engine();
  o.duration_s = 1;
  const auto a = generic::EvaluateGait(d, v, {2, 0.4, 0.2, 0.1}, o);
  const auto b = generic::EvaluateGait(d, v, {2, 0.4, 0.2, 0.1}, o);
  ASSERT_TRUE(a.valid) << a.reason;
  EXPECT_EQ(a.travel_m, b.travel_m);
  EXPECT_GT(std::fabs(a.travel_m), 1e-4);
  EXPECT_GT(a.servo_energy_j, 0);
  EXPECT_NEAR(a.weight_n, 0.045 * 9.81, 1e-6);
}

// A chain held by the world on sprung universal joints (tests/fixtures/robots/cantilever)
// sags under gravity to the same angles, about the same axes and in the same sense, in
// both builds: MuJoCo's two hinges per joint against ODE's universal joint.
TEST(MujocoWorld, UniversalJointsAgreeWithTheOdeBuild) {
  auto d = robots::LoadDescriptor(std::string(GAITFORGE_SOURCE_DIR) +
                                  "/tests/fixtures/robots/cantilever/robot.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  generic::ParamValues v(*d);
  ASSERT_TRUE(v.Set("joint.bend_damping_nms_per_rad", 0.01).ok());  // settle within 3 s
  sim::InitThread();
  auto ode = generic::GenericWorld::Build(*d, v, 0);
  auto mj = MujocoWorld::Build(*d, v, 0);
  ASSERT_TRUE(ode.ok()) << ode.status();
  ASSERT_TRUE(mj.ok()) << mj.status();
  for (auto* w : {static_cast<generic::RobotWorld*>(ode->get()), static_cast<generic::RobotWorld*>(mj->get())})
    while (w->time() < 3) ASSERT_TRUE(w->Step({}).ok);
  for (const std::string c : {"j1.angle1", "j2.angle1", "j3.angle1"}) {
    const double a = *(*ode)->Channel(c), b = *(*mj)->Channel(c);
    EXPECT_NEAR(b, a, 0.02 * std::fabs(a)) << c;
    EXPECT_NEAR(*(*mj)->Channel(c.substr(0, 3) + "angle2"), 0, 1e-6) << c;
  }
  EXPECT_NEAR(*(*mj)->Channel("tip.z"), *(*ode)->Channel("tip.z"), 1e-4);
}

}  // namespace
}  // namespace gaitforge::mujoco
