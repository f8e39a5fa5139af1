// PD servos on the generic builder (a servo with kp and kd: a torque kp (command - angle) -
// kd rate, at most max_torque; docs/robots.md), on an arm that a hinge holds out from the
// world: gravity's moment m g L/2 makes it sag by m g (L/2) cos(angle) / kp, a command
// turns it there less the same sag, and below the gravity load the torque saturates and
// the arm falls past where it would hold. The MuJoCo build agrees (its motor takes the same torque).
#include <algorithm>
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

std::string ArmText(const std::string& max_torque) {
  return std::string(R"(format: gaitforge.robot.v1
name: pd_arm
model: generic
parameters:
  arm: {length_m: {value: 0.2, range: [0.05, 1], unit: m}, mass_kg: {value: 0.5, range: [0.01, 5], unit: kg}}
  kp: {value: 20, range: [0.1, 1000], unit: N m/rad}
)") + testing::kSimulationParameters + R"(bodies:
  - {name: arm, shape: box, size: [arm.length_m, 0.02, 0.02], mass: arm.mass_kg, position: [0.5*arm.length_m, 0, 0.5]}
joints:
  - {name: hinge, type: hinge, bodies: [world, arm], anchor: [0, 0, 0.5], axis: [0, 1, 0]}
actuators:
  - {name: motor, type: servo, joint: hinge, kp: kp, kd: 0.5, max_torque: )" + max_torque + R"(, lag_s: 0}
ground: {friction: 1, erp: 0.2, cfm: 1.0e-6}
controller: {kind: sine, actuators: [motor], frequency_hz: [1, 2], amplitude_rad: [0, 1], offset_rad: [-1, 1]}
sensors:
  - {kind: joint_angle, names: [hinge]}
)";
}

class PdServoTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
};

// The hinge's angle after 1 s at `command` (rad).
template <typename World>
double HeldAngle(World& w, double command) {
  for (int i = 0; i < 1000; ++i) EXPECT_TRUE(w.Step({command}).ok);
  return *w.Channel("hinge.angle");
}

TEST_F(PdServoTest, GravitySagsTheArmByItsMomentOverKp) {
  auto d = robots::ParseDescriptor(ArmText("5"), "pd_arm.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ParamValues v(*d);
  auto w = GenericWorld::Build(*d, v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  const double moment = 0.5 * 9.81 * 0.1, kp = 20;
  const double sag = std::fabs(HeldAngle(**w, 0));
  EXPECT_NEAR(sag, moment * std::cos(sag) / kp, 0.01 * moment / kp);
  // Turned up by 0.3 rad (whichever sign lifts it), it sags by the moment there.
  for (double c : {0.3, -0.3}) {
    const double a = HeldAngle(**w, c);
    EXPECT_NEAR(std::fabs(c - a), moment * std::cos(std::fabs(a)) / kp, 0.02 * moment / kp) << c;
  }
  EXPECT_GT((*w)->servo_energy(), 0);
  // MuJoCo's motor takes the same torque: the same sag.
  auto m = mujoco::MujocoWorld::Build(*d, v, 0);
  ASSERT_TRUE(m.ok()) << m.status();
  EXPECT_NEAR(std::fabs(HeldAngle(**m, 0)), sag, 0.02 * sag);
}

TEST_F(PdServoTest, BelowTheGravityLoadTheTorqueSaturatesAndTheArmFalls) {
  auto d = robots::ParseDescriptor(ArmText("0.3"), "pd_arm.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ParamValues v(*d);
  auto w = GenericWorld::Build(*d, v, 0);
  ASSERT_TRUE(w.ok()) << w.status();
  // Saturated, the servo's torque is 0.3 N m against a moment of 0.49 cos(angle): the arm
  // swings about cos(angle) = 0.61 (0.91 rad), undamped, far past the 0.025 rad it sags
  // with torque to spare.
  double widest = 0;
  for (int i = 0; i < 1000; ++i) {
    ASSERT_TRUE((*w)->Step({0}).ok);
    widest = std::max(widest, std::fabs(*(*w)->Channel("hinge.angle")));
  }
  EXPECT_GT(widest, 0.91);
  EXPECT_GT((*w)->torque_limited_fraction(), 0.5);
}

TEST_F(PdServoTest, BadGainsAndMixedControlLawsAreRefused) {
  auto mixed = robots::ParseDescriptor(
      [] {
        std::string t = ArmText("5");
        t.replace(t.find("kp: kp,"), 7, "kp: kp, gain: 50,");
        return t;
      }(),
      "pd_arm.yaml");
  ASSERT_FALSE(mixed.ok());
  EXPECT_NE(std::string(mixed.status().message()).find(
                "actuators[0].gain: a PD servo (kp, kd) has no speed command"),
            std::string::npos)
      << mixed.status();
  auto d = robots::ParseDescriptor(ArmText("0"), "pd_arm.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ParamValues v(*d);
  auto w = GenericWorld::Build(*d, v, 0);
  ASSERT_FALSE(w.ok());
  EXPECT_NE(std::string(w.status().message()).find("PD servo motor needs kp > 0, kd >= 0, max_torque > 0"),
            std::string::npos)
      << w.status();
}

}  // namespace
}  // namespace gaitforge::generic
