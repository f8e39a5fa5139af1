// A robot that exists only as files in a test fixture (tests/fixtures/robots/twobox/) runs a
// GA gait study through the real CLI, coordinator and workers: the spec names the robot's
// folder, the study carries its descriptor, and the result does not depend on the number of
// workers. Bad robot references are refused before anything starts, naming the lines.
#include <filesystem>
#include <regex>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

std::string Fixture() { return std::string(GAITFORGE_SOURCE_DIR) + "/tests/fixtures/robots/twobox"; }

std::string Spec(const std::string& robot) {
  return "name: twobox-ga\nseed: 3\nengine: ga\npopulation: 12\ngenerations: 3\n"
         "objective:\n  name: robot.distance\n  robot: " + robot + "\nga:\n  elite: 2\n";
}

// Runs the study with `workers` worker processes; returns its hall of fame as JSON.
std::string RunStudy(const TempDir& dir, const std::string& db, int workers) {
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge") + " --db " + db;
  auto r = RunCommand(cli + " local spec.yaml --workers " + std::to_string(workers));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("completed after 3 generations"));
  auto list = RunCommand(cli + " list");
  const std::string id = list.out.substr(list.out.find('\n') + 1, list.out.find(' ', list.out.find('\n') + 1) - list.out.find('\n') - 1);
  auto hof = RunCommand(cli + " hof " + id + " --json");
  EXPECT_EQ(hof.exit_code, 0) << hof.err;
  // The best gait as the servo's set-points, with its speed limit from the descriptor.
  auto exported = RunCommand(cli + " export " + id + " --rate 50 --cycles 1 --output gait.csv --json");
  EXPECT_EQ(exported.exit_code, 0) << exported.err;
  EXPECT_THAT(exported.out, AllOf(HasSubstr("\"controller\":\"sine\""),
                                  HasSubstr("\"name\":\"servo\",\"max_rate_per_s\":"),
                                  HasSubstr("\"max_speed_rad_per_s\":")));
  EXPECT_EQ(ReadFile(dir.File("gait.csv")).substr(0, 8), "t,servo\n");
  auto show = RunCommand(cli + " show " + id + " --json");
  EXPECT_THAT(show.out, AllOf(HasSubstr("\"robot\":\"twobox\""), HasSubstr("\"robot_descriptor\":\"# A small robot")));
  return hof.out;
}

TEST(RobotStudy, AFixtureRobotEvolvesAndItsResultIgnoresTheWorkerCount) {
  TempDir dir;
  WriteFile(dir.File("spec.yaml"), Spec(Fixture()));
  const std::string one = RunStudy(dir, "one.db", 1);
  const std::string two = RunStudy(dir, "two.db", 2);
  EXPECT_THAT(one, AllOf(HasSubstr("fitness"), HasSubstr("\"distance_per_cycle\":")));
  // JSON maps (the metrics) have no fixed order; everything else must match byte for byte.
  const std::regex metrics(R"re("metrics":\{[^}]*\})re");
  EXPECT_EQ(std::regex_replace(one, metrics, ""), std::regex_replace(two, metrics, ""));
}

TEST(RobotStudy, BadRobotReferencesAreRefusedWithTheirLines) {
  TempDir dir;
  auto run = [&](const std::string& spec) {
    WriteFile(dir.File("spec.yaml"), spec);
    return RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " local spec.yaml --workers 1");
  };
  auto missing = run(Spec("no/such/robot.yaml"));
  EXPECT_EQ(missing.exit_code, 3);  // not found, as a missing recording
  EXPECT_THAT(missing.err, AllOf(HasSubstr("spec.yaml:8:3: field 'objective.robot'"),
                                 HasSubstr("cannot open")));
  std::string text = ReadFile(Fixture() + "/robot.yaml");
  text.replace(text.find("bodies: [rear, front]"), 21, "bodies: [rear, frnt]");
  WriteFile(dir.File("bad/robot.yaml"), text);
  auto bad = run(Spec("bad"));
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.err, AllOf(HasSubstr("spec.yaml:8:3"), HasSubstr("bad/robot.yaml:"),
                             HasSubstr("no body named 'frnt'")));
  EXPECT_FALSE(std::filesystem::exists(dir.File("runs/gaitforge.db")));  // nothing stored
  // The caterpillar is a robot on the generic builder: robot.distance runs it.
  auto caterpillar = run(Spec("caterpillar"));
  EXPECT_EQ(caterpillar.exit_code, 0) << caterpillar.err;
  EXPECT_THAT(caterpillar.out + caterpillar.err, HasSubstr("completed after 3 generations"));
}

}  // namespace
}  // namespace gaitforge::testing
