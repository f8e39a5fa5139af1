// The motors' electrical power (workers/models/generic/power_meter.h): tau w + 1.5 R i^2 per
// motor with i = tau / (gear kt), the standby power on top, and only regen_efficiency of a
// braking bus returned. Checked by hand on numbers, then on an arm a PD servo holds out
// against gravity (the holding torque costs copper loss only), on both engines.
#include "workers/models/generic/power_meter.h"

#include <cmath>
#include <fstream>
#include <string>

#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "tests/support/robot_text.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/models/generic/generic_world.h"
#include "workers/models/mujoco/mujoco_world.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

// An arm a PD servo holds out from the world, its motor geared 10:1 with kt 0.1 N m/A and
// R 0.5 ohm on a 24 V bus that the electronics draw 0.2 A from.
std::string ArmText(const std::string& regen) {
  return std::string(R"(format: gaitforge.robot.v1
name: geared_arm
model: generic
parameters:
  arm: {length_m: {value: 0.2, range: [0.05, 1], unit: m}, mass_kg: {value: 0.5, range: [0.01, 5], unit: kg}}
  motor: {resistance_ohm: {value: 0.5, range: [0, 5], unit: ohm}}
)") + testing::kSimulationParameters +
         R"(bodies:
  - {name: arm, shape: box, size: [arm.length_m, 0.02, 0.02], mass: arm.mass_kg, position: [0.5*arm.length_m, 0, 0.5]}
joints:
  - {name: hinge, type: hinge, bodies: [world, arm], anchor: [0, 0, 0.5], axis: [0, 1, 0]}
actuators:
  - {name: motor, type: servo, joint: hinge, kp: 40, kd: 0.5, max_torque: 5, lag_s: 0}
ground: {friction: 1, erp: 0.2, cfm: 1.0e-6}
controller: {kind: sine, actuators: [motor], frequency_hz: [0.5, 2], amplitude_rad: [0, 1], offset_rad: [-1, 1]}
electrical:
  bus_voltage: 24
  standby_current: 0.2
  regen_efficiency: )" +
         regen + R"(
  motors:
    - {actuators: [motor], gear: 10, kt: 0.1, resistance: motor.resistance_ohm}
)";
}

class PowerMeterTest : public ::testing::Test {
 protected:
  void SetUp() override { sim::InitThread(); }
  robots::RobotDescriptor Arm(const std::string& regen) {
    auto d = robots::ParseDescriptor(ArmText(regen), "geared_arm.yaml");
    EXPECT_TRUE(d.ok()) << d.status();
    return *d;
  }
};

TEST_F(PowerMeterTest, MechanicalPowerPlusCopperLossPlusStandby) {
  const robots::RobotDescriptor d = Arm("0.5");
  ParamValues v(d);
  auto made = PowerMeter::For(d, v);
  ASSERT_TRUE(made.ok()) << made.status();
  auto& m = *made;
  ASSERT_NE(m, nullptr);
  // 2 N m at the joint: 0.2 N m at the rotor, 2 A, 1.5 x 0.5 x 4 = 3 W in the windings.
  EXPECT_DOUBLE_EQ(m->Power({2.0}, {0.0}), 4.8 + 3.0);
  EXPECT_DOUBLE_EQ(m->Power({2.0}, {1.5}), 4.8 + 3.0 + 3.0);
  // Braking: -2 N m at 3 rad/s is -6 W mechanical, the bus -6 + 3 + 4.8 = 1.8 W: still a draw.
  EXPECT_DOUBLE_EQ(m->Power({-2.0}, {3.0}), 1.8);
  // -2 N m at 10 rad/s: the bus at -20 + 7.8 = -12.2 W, half of which comes back.
  EXPECT_DOUBLE_EQ(m->Power({-2.0}, {10.0}), -6.1);
  auto none = *PowerMeter::For(Arm("0"), v);
  EXPECT_DOUBLE_EQ(none->Power({-2.0}, {10.0}), 0.0);
  m->Step({2.0}, {0.0}, 0.5);
  m->Step({2.0}, {1.5}, 0.5);
  EXPECT_DOUBLE_EQ(m->energy_j(), 0.5 * 7.8 + 0.5 * 10.8);
  EXPECT_DOUBLE_EQ(m->seconds(), 1.0);
  // A parameter the section names follows the values it is built with.
  ASSERT_TRUE(v.Set("motor.resistance_ohm", 1.0).ok());
  EXPECT_DOUBLE_EQ((*PowerMeter::For(d, v))->Power({2.0}, {0.0}), 4.8 + 6.0);
}

// The servo's torque and rate as the worlds report them: held out, the arm's torque is
// gravity's moment, its rate 0, and the battery pays the standby and the copper loss.
TEST_F(PowerMeterTest, HoldingAnArmCostsItsCopperLossOnBothEngines) {
  const robots::RobotDescriptor d = Arm("0");
  ParamValues v(d);
  auto meter = *PowerMeter::For(d, v);
  auto ode = GenericWorld::Build(d, v, 0);
  ASSERT_TRUE(ode.ok()) << ode.status();
  auto mj = mujoco::MujocoWorld::Build(d, v, 0);
  ASSERT_TRUE(mj.ok()) << mj.status();
  for (RobotWorld* w :
       {static_cast<RobotWorld*>(ode->get()), static_cast<RobotWorld*>(mj->get())}) {
    for (int i = 0; i < 2000; ++i) ASSERT_TRUE(w->Step({0.0}).ok);
    const double angle = *w->Channel("hinge.angle");
    const double moment = 0.5 * 9.81 * 0.1 * std::cos(angle);
    ASSERT_EQ(w->actuator_torques().size(), 1u);
    EXPECT_NEAR(std::fabs(w->actuator_torques()[0]), moment, 0.01 * moment);
    EXPECT_NEAR(w->actuator_rates()[0], 0.0, 1e-3);
    const double current = moment / (10 * 0.1);
    EXPECT_NEAR(meter->Power(w->actuator_torques(), w->actuator_rates()),
                24 * 0.2 + 1.5 * 0.5 * current * current, 0.02);
  }
}

// A gait's battery energy is the meter's over the measured cycles; swinging costs more
// than the standby, and a dearer winding more still.
TEST_F(PowerMeterTest, AGaitReportsTheBatterysEnergyOverItsMeasuredCycles) {
  const robots::RobotDescriptor d = Arm("0");
  ParamValues v(d);
  GaitOptions o;
  o.settle_cycles = 1;
  o.measured_cycles = 2;
  const GaitResult g = EvaluateGait(d, v, {1.0, 0.8, 0.0, 0.0}, o);
  ASSERT_TRUE(g.valid) << g.reason;
  ASSERT_TRUE(g.electrical);
  EXPECT_NEAR(g.measured_s, 2.0, 1e-9);
  EXPECT_GT(g.electrical_energy_j, 24 * 0.2 * 2.0 + 0.1) << g.electrical_energy_j;
  ASSERT_TRUE(v.Set("motor.resistance_ohm", 2.0).ok());
  const GaitResult dear = EvaluateGait(d, v, {1.0, 0.8, 0.0, 0.0}, o);
  EXPECT_GT(dear.electrical_energy_j, g.electrical_energy_j + 0.1) << dear.electrical_energy_j;
}

// A learned current model is asked at the rate of its recordings and held between: here a
// network whose current is the servo's torque (one linear layer), asked at 100 Hz while the
// world steps at 1 kHz, integrates the torque sampled every tenth step.
TEST_F(PowerMeterTest, ALearnedModelIsAskedAtItsRecordingsRate) {
  const std::string dir = ::testing::TempDir();
  std::ofstream(dir + "/linear.mlp.json")
      << R"({"format": "gaitforge.mlp.v1", "inputs": ["motor.torque"], "outputs": ["bus.current"],
 "activation": "relu", "input_mean": [0], "input_sd": [1], "output_mean": [0], "output_sd": [1],
 "layers": [{"weights": [[1]], "bias": [0]}]})";
  std::string text = ArmText("0");
  text.replace(text.find("  motors:"), 0,
               "  current_model: linear.mlp.json\n  current_model_rate_hz: 100\n");
  auto d = robots::ParseDescriptor(text, dir + "/geared_arm.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ParamValues v(*d);
  auto meter = *PowerMeter::For(*d, v);
  ASSERT_TRUE(meter->learned());
  double expected = 0;
  for (int i = 0; i < 100; ++i) {  // 0.1 s of a torque ramp at 1 ms steps
    const double torque = 0.01 * i;
    meter->Step({torque}, {0.0}, 0.001);
    expected += 24 * 0.01 * (i - i % 10) * 0.001;  // the torque of the last tenth step
  }
  EXPECT_NEAR(meter->energy_j(), expected, 1e-12);
  EXPECT_DOUBLE_EQ(meter->Power({0.5}, {0.0}), 24 * 0.5);
  // A rate without a model is refused.
  text.replace(text.find("  current_model: linear.mlp.json\n"), 33, "");
  auto orphan = robots::ParseDescriptor(text, dir + "/geared_arm.yaml");
  ASSERT_FALSE(orphan.ok());
  EXPECT_NE(orphan.status().message().find(
                "electrical.current_model_rate_hz: belongs to a current_model"),
            std::string::npos)
      << orphan.status();
}

}  // namespace
}  // namespace gaitforge::generic
