// A descriptor's electrical section (robots/electrical_parser.h): the Go2's is read with its
// motors and numbers, and a bad one is refused with the file, line, field and what is allowed.
// And the sensors a current model reads: joint_torque and joint_rate groups of servos.
#include <algorithm>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"

namespace gaitforge::robots {
namespace {

// The Go2's descriptor with its electrical section (to the end of its calf motors' line)
// replaced by `section`.
std::string Go2With(const std::string& section) {
  std::string text(BuiltinText("go2_castors"));
  const size_t at = text.find("\nelectrical:\n");
  const std::string last = "resistance: motor.resistance_ohm}\n";
  const size_t end = text.rfind(last);
  EXPECT_TRUE(at != std::string::npos && end != std::string::npos && end > at)
      << "the Go2's electrical section moved; update this test";
  return text.replace(at + 1, end + last.size() - at - 1, section);
}

TEST(ElectricalParserTest, TheGo2DrivesTwelveJointsWithTwoMotorTypesOnA28VBattery) {
  const RobotDescriptor& go2 = Robot("go2_castors");
  ASSERT_TRUE(go2.electrical.has_value());
  const auto value = [&go2](const std::string& n) { return go2.Value(n); };
  EXPECT_DOUBLE_EQ(go2.electrical->bus_voltage.Eval(value), 28.8);
  ASSERT_EQ(go2.electrical->motors.size(), 2u);
  EXPECT_EQ(go2.electrical->motors[0].actuators.size() + go2.electrical->motors[1].actuators.size(),
            12u);
  EXPECT_DOUBLE_EQ(go2.electrical->motors[0].gear.Eval(value), 6.33);
  EXPECT_NEAR(go2.electrical->motors[1].gear.Eval(value) / 6.33, 1.917, 0.001);
  EXPECT_FALSE(Robot("caterpillar").electrical.has_value());
}

TEST(ElectricalParserTest, TheGo2RecordsItsServosTorquesAndRates) {
  const std::vector<std::string> channels = Robot("go2_castors").Channels();
  for (const char* c : {"hip_fr.angle", "hip_fr.rate", "calf_rl.torque"})
    EXPECT_NE(std::find(channels.begin(), channels.end(), c), channels.end()) << c;
  std::string text(BuiltinText("go2_castors"));
  const std::string line = "  - {kind: joint_torque, names: [hip_fr,";
  ASSERT_NE(text.find(line), std::string::npos);
  text.replace(text.find(line), line.size(), "  - {kind: joint_torque, names: [castor_fr,");
  auto d = ParseDescriptor(text, "go2.yaml");
  ASSERT_FALSE(d.ok());
  EXPECT_NE(
      d.status().message().find("no servo actuator named 'castor_fr' (joint_torque names servos)"),
      std::string::npos)
      << d.status();
}

struct BadCase {
  std::string name, section, message;
};

class ElectricalParserErrorTest : public ::testing::TestWithParam<BadCase> {};

TEST_P(ElectricalParserErrorTest, IsRefusedWithWhereAndWhy) {
  auto d = ParseDescriptor(Go2With(GetParam().section), "go2.yaml");
  ASSERT_FALSE(d.ok());
  EXPECT_NE(std::string(d.status().message()).find(GetParam().message), std::string::npos)
      << d.status().message();
  EXPECT_NE(std::string(d.status().message()).find("go2.yaml:"), std::string::npos);
}

const std::string kHead =
    "electrical:\n  bus_voltage: power.bus_voltage_v\n  standby_current: power.standby_current_a\n";
const std::string kRegen = "  regen_efficiency: power.regen_efficiency\n";
const std::string kMotor =
    "gear: motor.gear_hip, kt: motor.kt_nm_per_a, resistance: motor.resistance_ohm}\n";

INSTANTIATE_TEST_SUITE_P(
    Cases, ElectricalParserErrorTest,
    ::testing::Values(
        BadCase{"NoMotors", kHead + kRegen, "electrical.motors: missing"},
        BadCase{"NotAServo", kHead + kRegen + "  motors:\n    - {actuators: [knee], " + kMotor,
                "electrical.motors[0].actuators: 'knee' is not a servo actuator of go2_castors"},
        BadCase{"TwoMotors",
                kHead + kRegen + "  motors:\n    - {actuators: [hip_fr], " + kMotor +
                    "    - {actuators: [hip_fr], " + kMotor,
                "electrical.motors[1].actuators: 'hip_fr' has a motor already"},
        BadCase{"RegenAboveOne",
                kHead + "  regen_efficiency: 1.5\n  motors:\n    - {actuators: [hip_fr], " + kMotor,
                "electrical.regen_efficiency: is 1.5; must be in [0, 1]"},
        BadCase{"GearBelowOne",
                kHead + kRegen +
                    "  motors:\n    - {actuators: [hip_fr], gear: 0.5, kt: 0.1, resistance: 0.1}\n",
                "electrical.motors[0].gear: is 0.5; must be >= 1"},
        BadCase{
            "UnknownParameter",
            kHead + kRegen +
                "  motors:\n    - {actuators: [hip_fr], gear: 6, kt: motor.kt, resistance: 0.1}\n",
            "motor.kt"},
        BadCase{"UnknownKey",
                kHead + kRegen + "  voltage: 3\n  motors:\n    - {actuators: [hip_fr], " + kMotor,
                "voltage"}),
    [](const ::testing::TestParamInfo<BadCase>& i) { return i.param.name; });

}  // namespace
}  // namespace gaitforge::robots
