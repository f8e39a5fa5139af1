// A robust caterpillar study (objective.robust: numeric variants, start phases and sampled
// force, through the real CLI, coordinator, workers and SQLite) gives the same individuals
// with one worker and, killed with -9 and resumed, with two; each member's fitness is kept
// in the metrics.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <thread>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

using ::testing::HasSubstr;

constexpr char kSpec[] =
    "name: robust\nseed: 4\npopulation: 6\ngenerations: 30\n"
    "objective:\n  name: caterpillar.distance\n  params: {cycles: 1, settle_cycles: 0}\n"
    "  robust:\n    numerics: [\"\", \"simulation.timestep_s=0.00125\"]\n"
    "    start_phases: 2\n"
    "    parameters:\n      - {name: actuators.force_n, lo: 8, hi: 9.5}\n"
    "    statistic: mean_minus_sd\n"
    "ga:\n  elite: 2\n";

TEST(RobustStudy, IgnoresTheWorkerCountAndAKillAndKeepsEveryMember) {
  TempDir dir;
  WriteFile(dir.File("spec.yaml"), kSpec);
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge") + " --db ";
  auto whole = RunCommand(cli + "whole.db local spec.yaml --workers 1");
  ASSERT_EQ(whole.exit_code, 0) << whole.err;

  RunCommand("cd " + dir.path() + " && { " + Bin("gaitforge") +
             " --db " + dir.File("killed.db") + " local spec.yaml --workers 2 > local.out 2> local.err & "
             "echo $! > local.pid; }");
  const std::string id = WaitForGenerations(cli + dir.File("killed.db"), 2);
  ASSERT_FALSE(id.empty()) << ReadFile(dir.File("local.err"));
  RunCommand("kill -9 " + std::to_string(std::stoi(ReadFile(dir.File("local.pid")))));
  // Its coordinator and workers get SIGTERM from the kernel; resume once they are gone.
  // (The pattern is read from a file so that the shell running pgrep does not match it.)
  WriteFile(dir.File("orphans.re"), dir.File("killed.db"));
  for (int i = 0; i < 600; ++i) {
    if (RunCommand("pgrep -f -- \"$(cat " + dir.File("orphans.re") + ")\"").out.empty()) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  auto resume = RunCommand(cli + dir.File("killed.db") + " resume " + id + " --workers 2");
  ASSERT_EQ(resume.exit_code, 0) << resume.err;

  const std::string q =
      "SELECT generation, member, hex(genes), valid, fitness FROM individuals "
      "ORDER BY generation, member";
  const auto a = Rows(dir.File("whole.db"), q), b = Rows(dir.File("killed.db"), q);
  EXPECT_EQ(a.size(), 180u);
  EXPECT_EQ(a, b);
  const std::string whole_id = WaitForGenerations(cli + "whole.db", 30);
  auto members = RunCommand(cli + "whole.db individuals " + whole_id + " --generation 0 --json");
  EXPECT_THAT(members.out, HasSubstr("\"member.3\""));
  EXPECT_THAT(members.out, HasSubstr("\"robust.sd\""));

  // The best gait as the valves' timeline: 1/0 per actuator, consistent with its windows.
  auto exported = RunCommand(cli + "whole.db export " + whole_id +
                             " --rank 0 --rate 200 --cycles 2 --output gait.csv --json");
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  EXPECT_THAT(exported.out, HasSubstr("\"controller\":\"phase_onoff\""));
  EXPECT_THAT(exported.out, HasSubstr("\"on_windows_s\":["));
  const std::string csv = ReadFile(dir.File("gait.csv"));
  EXPECT_EQ(csv.substr(0, csv.find('\n')), "t,T1,T2,T3,B1,B2,B3");
  const size_t at = exported.out.find("\"period_s\":") + 11;
  const double period = std::atof(exported.out.c_str() + at);
  const size_t lines = std::count(csv.begin(), csv.end(), '\n');
  EXPECT_EQ(lines, 1 + static_cast<size_t>(std::floor(2 * period * 200 + 1e-9)) + 1);
  EXPECT_EQ(csv.find_first_not_of("0123456789.,-\ntTB"), std::string::npos);
  auto bad = RunCommand(cli + "whole.db export " + whole_id + " --rank 99 --output x.csv");
  EXPECT_EQ(bad.exit_code, 3);
}

}  // namespace
}  // namespace gaitforge::testing
