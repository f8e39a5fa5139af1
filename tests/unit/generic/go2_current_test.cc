// Paper 002's learned current model for the Go2 (robots/go2_castors/current.mlp.json, trained
// by bench/go2/current_model.py on a motor reference richer than the motor model): it
// reproduces a held-out recording (the test repeat's trot and slide at 0.22 m/s,
// tests/fixtures/go2/current_held_out.csv), the descriptor's meter uses it, and a model that
// does not match the robot's joints is refused with the file and the input named.
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "gtest/gtest.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_world.h"
#include "workers/models/generic/power_meter.h"

namespace gaitforge::generic {
namespace {

struct Rows {
  std::vector<std::string> names;
  std::vector<std::vector<double>> rows;
};

Rows ReadFixture() {
  std::ifstream in(std::string(GAITFORGE_SOURCE_DIR) + "/tests/fixtures/go2/current_held_out.csv");
  EXPECT_TRUE(in) << "the fixture is missing";
  Rows r;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream s(line);
    std::string cell;
    std::vector<std::string> cells;
    while (std::getline(s, cell, ',')) cells.push_back(cell);
    if (r.names.empty()) {
      r.names = cells;
      continue;
    }
    std::vector<double> row;
    for (const auto& c : cells) row.push_back(std::stod(c));
    r.rows.push_back(row);
  }
  return r;
}

TEST(Go2CurrentTest, TheLearnedModelReproducesAHeldOutRecording) {
  const robots::RobotDescriptor& go2 = robots::Robot("go2_castors");
  ParamValues v(go2);
  auto made = PowerMeter::For(go2, v);
  ASSERT_TRUE(made.ok()) << made.status();
  ASSERT_TRUE((*made)->learned());
  const Rows f = ReadFixture();
  ASSERT_EQ(f.names.size(), 26u);  // gait, 12 torques, 12 rates, bus.current
  ASSERT_GE(f.rows.size(), 1000u);
  // Each row's inputs into the meter's per-actuator vectors, by the channels' names.
  std::vector<int> slot;
  for (size_t c = 1; c + 1 < f.names.size(); ++c) {
    const std::string base = f.names[c].substr(0, f.names[c].rfind('.'));
    for (size_t i = 0; i < go2.actuators.size(); ++i)
      if (go2.actuators[i].name == base) slot.push_back(static_cast<int>(i));
  }
  ASSERT_EQ(slot.size(), 24u);
  double se = 0, ae = 0, mean = 0, var = 0;
  const double volts = (*made)->bus_voltage();
  for (const auto& row : f.rows) mean += row.back() / f.rows.size();
  for (const auto& row : f.rows) {
    std::vector<double> torque(go2.actuators.size()), rate(go2.actuators.size());
    for (size_t c = 1; c + 1 < row.size(); ++c)
      (f.names[c].ends_with(".torque") ? torque : rate)[slot[c - 1]] = row[c];
    const double err = (*made)->Power(torque, rate) / volts - row.back();
    se += err * err;
    ae += std::fabs(err);
    var += (row.back() - mean) * (row.back() - mean);
  }
  const double r2 = 1 - se / var, mae = ae / f.rows.size();
  // The bench's whole test repeat measured R2 0.997 and MAE 0.050 A (robots/go2_castors/README.md).
  EXPECT_GT(r2, 0.98) << mae;
  EXPECT_LT(mae, 0.15) << r2;
}

TEST(Go2CurrentTest, AModelThatDoesNotMatchTheJointsIsRefused) {
  // The Go2's descriptor from a file beside a network whose first input names no servo.
  const std::string dir = ::testing::TempDir();
  std::string net(robots::BuiltinFile("go2_castors", "current.mlp.json"));
  ASSERT_FALSE(net.empty());
  const size_t at = net.find("\"hip_fr.torque\"");
  ASSERT_NE(at, std::string::npos);
  net.replace(at, 15, "\"hip_xx.torque\"");
  std::ofstream(dir + "/other.mlp.json") << net;
  std::string text(robots::BuiltinText("go2_castors"));
  const size_t m = text.find("current_model: current.mlp.json");
  ASSERT_NE(m, std::string::npos);
  text.replace(m, 31, "current_model: other.mlp.json");
  text.replace(text.find("name: go2_castors"), 17, "name: go2_other");
  auto d = robots::ParseDescriptor(text, dir + "/robot.yaml");
  ASSERT_TRUE(d.ok()) << d.status();
  ParamValues v(*d);
  auto made = PowerMeter::For(*d, v);
  ASSERT_FALSE(made.ok());
  EXPECT_NE(made.status().message().find("input 'hip_xx.torque' is not a servo's torque or rate"),
            std::string::npos)
      << made.status();
  EXPECT_NE(made.status().message().find("electrical.current_model other.mlp.json"),
            std::string::npos);
  // And one that is not there says where it looked.
  text.replace(text.find("other.mlp.json"), 14, "gone.mlp.json");
  auto gone = robots::ParseDescriptor(text, dir + "/robot.yaml");
  ASSERT_TRUE(gone.ok());
  auto missing = PowerMeter::For(*gone, ParamValues(*gone));
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.status().message().find("cannot read " + dir), std::string::npos)
      << missing.status();
}

}  // namespace
}  // namespace gaitforge::generic
