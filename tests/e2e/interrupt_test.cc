// A study outlives its coordinator: after a lost coordinator or Ctrl-C the CLI says how to
// continue, `list` calls the study interrupted, and commands beside a running `gaitforge
// local` talk to its coordinator instead of failing on the database's lock.
#include <gtest/gtest.h>

#include <chrono>
#include <regex>
#include <thread>

#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

// About 20 ms per generation with one worker.
constexpr char kLong[] = "name: long\nseed: 7\npopulation: 10\ngenerations: 100\nobjective:\n"
                         "  name: analytic.rastrigin\n  params: {work_us: 2000}\nga: {elite: 2}\n";

class Interrupt : public ::testing::Test {
 protected:
  void SetUp() override { WriteFile(dir_.File("s.yaml"), kLong); }
  CommandResult Cli(const std::string& args) {
    return RunCommand("cd " + dir_.path() + " && " + Bin("gaitforge") + " " + args);
  }
  // Starts `gaitforge ARGS` in the background; returns its pid.
  std::string Background(const std::string& args, const std::string& name) {
    RunCommand("cd " + dir_.path() + " && { " + Bin("gaitforge") + " " + args + " > " + name +
               ".out 2> " + name + ".err & echo $! > " + name + ".pid; }");
    return std::to_string(std::stoi(ReadFile(dir_.File(name + ".pid"))));
  }
  // Waits (bounded) for `done`; the bound only stops a hung test.
  template <typename F>
  bool WaitFor(F done) {
    for (int i = 0; i < 1200; ++i) {
      if (done()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }
  bool Exited(const std::string& pid) { return RunCommand("kill -0 " + pid).exit_code != 0; }
  // The study's id once `generations` generations are stored, read beside the writer.
  std::string RunningStudy(int generations) {
    std::string id;
    WaitFor([&] {
      const std::string out = Cli("list --json").out;
      const size_t at = out.find("\"generations_done\":");
      if (at == std::string::npos || std::atoi(out.c_str() + at + 19) < generations) return false;
      const size_t from = out.find("\"study_id\":\"") + 12;
      id = out.substr(from, out.find('"', from) - from);
      return true;
    });
    return id;
  }
  std::string State() {
    const auto rows = Rows(dir_.File("runs/gaitforge.db"), "SELECT state FROM studies");
    return rows.empty() ? "" : rows[0];
  }
  TempDir dir_;
};

TEST_F(Interrupt, CommandsBesideARunningLocalTalkToItsCoordinator) {
  const std::string local = Background("local s.yaml --workers 1", "local");
  const std::string id = RunningStudy(2);
  ASSERT_FALSE(id.empty()) << ReadFile(dir_.File("local.err"));
  const std::string watch = Background("watch " + id + " --json", "watch");
  auto cancel = Cli("cancel " + id);
  EXPECT_EQ(cancel.exit_code, 0) << cancel.err;
  EXPECT_EQ(cancel.out, id + " cancelled\n");
  EXPECT_NE(cancel.err.find("gaitforge: using the coordinator that holds runs/gaitforge.db"),
            std::string::npos)
      << cancel.err;
  ASSERT_TRUE(WaitFor([&] { return Exited(local) && Exited(watch); }));
  EXPECT_NE(ReadFile(dir_.File("local.err")).find("study " + id + " cancelled after"),
            std::string::npos)
      << ReadFile(dir_.File("local.err"));
  EXPECT_NE(ReadFile(dir_.File("watch.out")).find("STUDY_STATE_CANCELLED"), std::string::npos)
      << ReadFile(dir_.File("watch.err"));
  EXPECT_EQ(State(), "cancelled|");
}

TEST_F(Interrupt, ALostCoordinatorAndCtrlCSayHowToContinue) {
  const std::string local = Background("local s.yaml --workers 1", "local");
  const std::string id = RunningStudy(2);
  ASSERT_FALSE(id.empty()) << ReadFile(dir_.File("local.err"));
  // The coordinator dies (its pid is the lock file's first line).
  const std::string coordinator =
      std::to_string(std::stoi(ReadFile(dir_.File("runs/gaitforge.db.lock"))));
  ASSERT_EQ(RunCommand("kill -9 " + coordinator).exit_code, 0);
  ASSERT_TRUE(WaitFor([&] { return Exited(local); }));
  const std::string hint = "continue it with 'gaitforge resume " + id + "'";
  const std::string err = ReadFile(dir_.File("local.err"));
  EXPECT_NE(err.find("gaitforge: lost the coordinator while watching study " + id),
            std::string::npos)
      << err;
  EXPECT_NE(err.find(hint), std::string::npos) << err;
  // Nothing runs the study now: list and watch say so; the file still says running.
  EXPECT_EQ(State(), "running|");
  auto list = Cli("list");
  EXPECT_TRUE(std::regex_search(list.out, std::regex(id + " +interrupted "))) << list.out;
  auto watch = Cli("watch " + id);
  EXPECT_EQ(watch.exit_code, 1);
  EXPECT_NE(watch.err.find("study " + id + " is interrupted: no coordinator runs it"),
            std::string::npos)
      << watch.err;
  EXPECT_NE(watch.err.find(hint), std::string::npos) << watch.err;
  // The dashboard of the unheld file says so too, as `list --json` does.
  EXPECT_NE(Cli("list --json").out.find("STUDY_STATE_INTERRUPTED"), std::string::npos);
  const std::string dash = Background("dashboard --dashboard 127.0.0.1:0", "dash");
  ASSERT_TRUE(WaitFor([&] { return ReadFile(dir_.File("dash.out")).find(':') != std::string::npos; }));
  const std::string url = ReadFile(dir_.File("dash.out"));
  const int port = std::atoi(url.c_str() + url.rfind(':') + 1);
  const std::string studies = HttpGet(port, "/api/studies");
  EXPECT_NE(studies.find("STUDY_STATE_INTERRUPTED"), std::string::npos) << studies;
  EXPECT_EQ(studies.find("STUDY_STATE_RUNNING"), std::string::npos) << studies;
  ASSERT_EQ(RunCommand("kill -INT " + dash).exit_code, 0);
  ASSERT_TRUE(WaitFor([&] { return Exited(dash); }));

  // Ctrl-C during `resume`.
  const int before = std::stoi(Rows(dir_.File("runs/gaitforge.db"),
                                    "SELECT generations_done FROM studies")[0]);
  const std::string resume = Background("resume " + id + " --workers 1", "resume");
  ASSERT_FALSE(RunningStudy(before + 2).empty());
  ASSERT_EQ(RunCommand("kill -INT " + resume).exit_code, 0);
  ASSERT_TRUE(WaitFor([&] { return Exited(resume); }));
  const std::string interrupted = ReadFile(dir_.File("resume.err"));
  EXPECT_NE(interrupted.find("gaitforge: interrupted; study " + id +
                             " is stored in runs/gaitforge.db up to its last committed "
                             "generation: " + hint),
            std::string::npos)
      << interrupted;
  ASSERT_TRUE(WaitFor([&] { return Cli("list").out.find(" interrupted ") != std::string::npos; }));
  // And the hint works: the study ends as one run would.
  auto again = Cli("resume " + id + " --workers 1");
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(Rows(dir_.File("runs/gaitforge.db"), "SELECT state, generations_done FROM studies")[0],
            "completed|100|");
}

// A worker told to stop (SIGTERM) finishes the batch in hand for its coordinator; when
// the coordinator is gone, nobody would take the results, so it leaves the rest of the
// batch unevaluated (their leases expire) instead of simulating on for nothing.
TEST(Drain, AWorkerWhoseCoordinatorIsGoneAbandonsItsBatch) {
  TempDir dir;
  LocalCluster cluster(dir.path(), dir.File("r.db"), {"--metrics-listen", "127.0.0.1:0"});
  ASSERT_TRUE(cluster.ok());
  // One thread, a first batch of 4 jobs of 1 s each.
  WriteFile(dir.File("slow.yaml"),
            "name: slow\nseed: 3\npopulation: 8\ngenerations: 2\nobjective:\n"
            "  name: analytic.rastrigin\n  params: {work_us: 1000000}\nga: {elite: 2}\n");
  ASSERT_EQ(cluster.Cli("submit " + dir.File("slow.yaml")).exit_code, 0);
  cluster.StartWorkers(1);
  bool leased = false;
  for (int i = 0; i < 600 && !leased; ++i) {  // the bound only stops a hung test
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    const std::string m = HttpGet(cluster.metrics_port(), "/metrics");
    std::smatch hit;
    leased = std::regex_search(m, hit, std::regex(R"(\ngaitforge_leases_total ([0-9.e+]+))")) &&
             std::stod(hit[1]) > 0;
  }
  ASSERT_TRUE(leased);
  cluster.KillCoordinator();
  cluster.StopWorkers();
  const std::string log = ReadFile(dir.File("w0.log"));
  EXPECT_NE(log.find("the coordinator is gone"), std::string::npos) << log;
  EXPECT_TRUE(std::regex_search(log, std::regex("left [1-9][0-9]* of 4 jobs unevaluated"))) << log;
}

}  // namespace
}  // namespace gaitforge::testing
