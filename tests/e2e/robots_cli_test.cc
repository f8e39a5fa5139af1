// `gaitforge robots` through the real binary: it lists the built-in robots, shows one
// robot's descriptor as JSON scripts can read, and checks a descriptor file, naming the
// file, line and field of a mistake with exit code 2.
#include <algorithm>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "absl/strings/str_join.h"
#include "robots/registry.h"
#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

TEST(RobotsCli, ListsShowsAndChecksDescriptors) {
  auto list = RunCommand(Bin("gaitforge") + " robots");
  ASSERT_EQ(list.exit_code, 0) << list.err;
  EXPECT_THAT(list.out, HasSubstr("caterpillar  generic  13  18"));

  auto show = RunCommand(Bin("gaitforge") + " robots caterpillar --json");
  ASSERT_EQ(show.exit_code, 0) << show.err;
  EXPECT_THAT(show.out, AllOf(HasSubstr("\"name\": \"actuators.force_n\", \"value\": 8.8"),
                              HasSubstr("\"name\": \"scale.link_stiffness\""),
                              HasSubstr("\"name\": \"T\", \"lo\": 0.2, \"hi\": 2}"),
                              HasSubstr("\"m6.z\"")));
  // What the gap finder may and may not offer for a robot: its suspects, what it rules out.
  auto walker = RunCommand(Bin("gaitforge") + " robots walker");
  ASSERT_EQ(walker.exit_code, 0) << walker.err;
  EXPECT_THAT(walker.out, AllOf(HasSubstr("RULED OUT"), HasSubstr("tether.constant  nothing trails")));
  auto tigrillo = RunCommand(Bin("gaitforge") + " robots tigrillo --json");
  EXPECT_THAT(tigrillo.out, AllOf(HasSubstr("\"suspects\": [{\"id\": \"knee.hind_stiffness\""),
                                  HasSubstr("\"ruled_out\": []")));

  TempDir dir;
  const std::string bad = dir.path() + "/robot.yaml";
  std::string text = ReadFile(std::string(GAITFORGE_SOURCE_DIR) + "/robots/caterpillar/robot.yaml");
  const size_t at = text.find("{value: 0.030, range: [0.001, 1]");
  const auto line = std::to_string(1 + std::count(text.begin(), text.begin() + at, '\n'));
  text.replace(at, 13, "{value: -3.0");
  WriteFile(bad, text);
  auto check = RunCommand(Bin("gaitforge") + " robots " + bad);
  EXPECT_EQ(check.exit_code, 2);
  EXPECT_THAT(check.err, AllOf(HasSubstr(bad + ":" + line + ":"),
                               HasSubstr("lumps.mass_kg = -3 kg is outside [0.001, 1] kg")));

  auto unknown = RunCommand(Bin("gaitforge") + " robots centipede");
  EXPECT_EQ(unknown.exit_code, 3);
  EXPECT_THAT(unknown.err, HasSubstr("known: " + absl::StrJoin(robots::RobotNames(), ", ")));
}

}  // namespace
}  // namespace gaitforge::testing
