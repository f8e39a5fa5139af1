// Joint Coulomb friction (a hinge's `friction`, N m; paper 002's joints): an arm held out
// level by a hinge stays there while gravity's moment is below the friction and falls when
// it is above, on both engines; a hinge driven by a speed-command servo cannot also have
// friction in the ODE build, and only hinges have it.
#include <cmath>
#include <string>

#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "tests/support/robot_text.h"
#include "workers/models/generic/generic_world.h"
#include "workers/models/mujoco/mujoco_world.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

// A 0.5 kg, 0.2 m arm on a hinge: gravity's moment about it is 0.49 N m when level. Its
// servo is a PD servo too weak to matter (kp 1e-3), so what holds it is the friction.
std::string ArmText(const std::string& friction, const std::string& servo = "kp: 1.0e-3, kd: 0") {
  return std::string(R"(format: gaitforge.robot.v1
name: rubbing_arm
model: generic
parameters:
  joint: {friction_nm: {value: )") +
         friction + R"(, range: [0, 10], unit: N m}}
)" + testing::kSimulationParameters +
         R"(bodies:
  - {name: arm, shape: box, size: [0.2, 0.02, 0.02], mass: 0.5, position: [0.1, 0, 0.5]}
joints:
  - {name: hinge, type: hinge, bodies: [world, arm], anchor: [0, 0, 0.5], axis: [0, 1, 0], friction: joint.friction_nm}
actuators:
  - {name: motor, type: servo, joint: hinge, )" +
         servo + R"(, max_torque: 5, lag_s: 0}
ground: {friction: 1, erp: 0.2, cfm: 1.0e-6}
controller: {kind: sine, actuators: [motor], frequency_hz: [1, 2], amplitude_rad: [0, 1], offset_rad: [-1, 1]}
sensors:
  - {kind: joint_angle, names: [hinge]}
)";
}

class JointFrictionTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
};

template <typename World>
double AngleAfterOneSecond(World& w) {
  for (int i = 0; i < 1000; ++i) EXPECT_TRUE(w.Step({0.0}).ok);
  return *w.Channel("hinge.angle");
}

TEST_F(JointFrictionTest, HoldsBelowItsTorqueAndSlipsAbove) {
  for (const auto& [friction, holds] : {std::pair{"0.6", true}, std::pair{"0.3", false}}) {
    auto d = robots::ParseDescriptor(ArmText(friction), "arm.yaml");
    ASSERT_TRUE(d.ok()) << d.status();
    ParamValues v(*d);
    auto ode = GenericWorld::Build(*d, v, 0);
    ASSERT_TRUE(ode.ok()) << ode.status();
    auto mj = mujoco::MujocoWorld::Build(*d, v, 0);
    ASSERT_TRUE(mj.ok()) << mj.status();
    const double a_ode = std::fabs(AngleAfterOneSecond(**ode)),
                 a_mj = std::fabs(AngleAfterOneSecond(**mj));
    if (holds) {
      EXPECT_LT(a_ode, 0.01) << friction;
      EXPECT_LT(a_mj, 0.1) << friction;  // MuJoCo's friction loss is a soft constraint: it creeps
    } else {
      EXPECT_GT(a_ode, 0.5) << friction;
      EXPECT_GT(a_mj, 0.5) << friction;
    }
  }
}

TEST_F(JointFrictionTest, ASpeedServosHingeOrAUniversalJointIsRefused) {
  auto d = robots::ParseDescriptor(ArmText("0.6", "gain: 10, max_speed: 5"), "arm.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ParamValues v(*d);
  auto w = GenericWorld::Build(*d, v, 0);
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.status().message().find("whose motor cannot also be the joint's friction"),
            std::string::npos)
      << w.status();
  std::string text = ArmText("0.6");
  text.replace(text.find("type: hinge"), 11, "type: universal, axis2: [1, 0, 0]");
  auto u = robots::ParseDescriptor(text, "arm.yaml");
  ASSERT_FALSE(u.ok());
  EXPECT_NE(u.status().message().find("joints[0].friction: only a hinge has friction"),
            std::string::npos)
      << u.status();
}

}  // namespace
}  // namespace gaitforge::generic
