// Input the coordinator and the CLI must refuse, in words, before they create or change
// anything: each test compares the files on disk before and after.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>

#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

// Every path under dir (files and directories), relative to it.
std::set<std::string> Tree(const std::string& dir) {
  std::set<std::string> out;
  for (const auto& e : std::filesystem::recursive_directory_iterator(dir))
    out.insert(std::filesystem::relative(e.path(), dir).string());
  return out;
}

// Runs a command in dir; expects exit 2, `message` on stderr and no file added or removed.
void ExpectRefused(const TempDir& dir, const std::string& command, const std::string& message) {
  const auto before = Tree(dir.path());
  auto r = RunCommand("cd " + dir.path() + " && " + command);
  EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.err;
  EXPECT_NE(r.err.find(message), std::string::npos) << command << "\n" << r.err;
  EXPECT_EQ(Tree(dir.path()), before) << command;
}

TEST(Refusals, TheCoordinatorRefusesBadFlagsBeforeTouchingTheDatabase) {
  TempDir dir;
  const std::string coordinator = Bin("gaitforge-coordinator") + " --listen 127.0.0.1:0 ";
  ExpectRefused(dir, coordinator + "--db r.db --log-level verbose",
                "gaitforge-coordinator: --log-level: expected trace, debug, info, warn, error or "
                "off, got 'verbose'");
  ExpectRefused(dir, Bin("gaitforge-worker") + " --log-level loud",
                "gaitforge-worker: --log-level: expected trace, debug, info, warn, error or off, "
                "got 'loud'");
  ExpectRefused(dir, Bin("gaitforge-coordinator") + " --listen 127.0.0.1:99999 --db r.db",
                "--listen 127.0.0.1:99999: the port must be a number in [0, 65535]");
  ExpectRefused(dir, coordinator + "--db runz/r.db",
                "--db runz/r.db: folder runz does not exist; create it first");
  std::filesystem::create_directories(dir.File("data"));
  ExpectRefused(dir, coordinator + "--db data",
                "--db data is a directory; name the database file, e.g. data/gaitforge.db");
}

TEST(Refusals, TheCoordinatorRefusesAPortInUse) {
  TempDir dir;
  std::filesystem::create_directories(dir.File("first"));
  LocalCluster first(dir.File("first"), dir.File("first/r.db"));
  ASSERT_TRUE(first.ok());
  ExpectRefused(dir, Bin("gaitforge-coordinator") + " --listen " + first.target() + " --db r.db",
                "cannot listen on " + first.target() + ": the port is already in use");
  EXPECT_EQ(first.Cli("list").exit_code, 0);  // the first one still serves
}

TEST(Refusals, TheCoordinatorLogsTheMetricsPortItBound) {
  TempDir dir;
  LocalCluster cluster(dir.path(), dir.File("r.db"),
                       {"--metrics-listen", "127.0.0.1:0", "--log-level", "info"});
  ASSERT_TRUE(cluster.ok());
  ASSERT_GT(cluster.metrics_port(), 0);
  EXPECT_NE(ReadFile(dir.File("coordinator.log"))
                .find("metrics at http://127.0.0.1:" + std::to_string(cluster.metrics_port()) +
                      "/metrics"),
            std::string::npos)
      << ReadFile(dir.File("coordinator.log"));
}

TEST(Refusals, TheCliCreatesNothingOutsideTheDatabasesFolder) {
  TempDir dir;
  std::filesystem::create_directories(dir.File("data"));
  const std::string cli = Bin("gaitforge") + " ";
  // A directory as --db would put logs/ beside it (at / for `--db /data`).
  ExpectRefused(dir, cli + "list --db data",
                "gaitforge: --db data is a directory; name the database file, e.g. "
                "data/gaitforge.db");
  WriteFile(dir.File("s.yaml"),
            "population: 4\ngenerations: 1\nobjective: {name: analytic.sphere}\nga: {elite: 1}\n");
  ExpectRefused(dir, cli + "local s.yaml --db runz/x.db",
                "gaitforge: --db runz/x.db: folder runz does not exist; create it first");
  // A bad spec stops `local` before a database or a log exists.
  WriteFile(dir.File("twice.yaml"), "population: 4\npopulation: 5\n");
  ExpectRefused(dir, cli + "local twice.yaml",
                "twice.yaml:2:1: field 'population': written twice, on lines 1 and 2");
  ExpectRefused(dir, cli + "local data", "'data' is a directory; give a spec file");
}

}  // namespace
}  // namespace gaitforge::testing
