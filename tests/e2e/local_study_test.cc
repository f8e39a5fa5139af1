// End to end: the real coordinator, real worker processes and the CLI over loopback gRPC,
// checked against the SQLite file itself.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <regex>
#include <thread>

#include "clients/cli/cli.h"
#include "grpc/health/v1/health.grpc.pb.h"
#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

const char* kSpec = R"(name: e2e
seed: 2024
population: 40
generations: 12
objective:
  name: analytic.rastrigin
  params: {work_us: 200}
)";

std::string RunStudy(const TempDir& dir, const std::string& db, int workers) {
  return RunClusterStudy(dir, db, kSpec, workers);
}

TEST(EndToEnd, AStudyRunsOverGrpcAndIsStoredInSqlite) {
  TempDir dir;
  const std::string db = dir.File("runs/gf.db");
  std::filesystem::create_directories(dir.File("runs"));
  const std::string id = RunStudy(dir, db, 2);
  ASSERT_FALSE(id.empty());

  // The SQLite file itself.
  EXPECT_EQ(Rows(db, "SELECT state, generations_done, evaluations FROM studies")[0],
            "completed|12|370|");  // 40 + 11 x 30: elites are not evaluated again
  EXPECT_EQ(Rows(db, "SELECT COUNT(*), COUNT(DISTINCT generation) FROM individuals")[0],
            "480|12|");
  EXPECT_EQ(Rows(db, "SELECT COUNT(*) FROM hall_of_fame")[0], "120|");
  // Results name the workers that computed them (which of the two did how much is timing).
  EXPECT_EQ(Rows(db, "SELECT COUNT(*) FROM individuals WHERE carried = 0 AND "
                     "worker_id NOT IN ('w0', 'w1')")[0],
            "0|");
  EXPECT_EQ(Rows(db, "PRAGMA integrity_check")[0], "ok|");
  // Hall-of-fame history: each generation's best is at least the previous one's.
  const auto best = Rows(db, "SELECT fitness FROM hall_of_fame WHERE rank = 0 ORDER BY generation");
  ASSERT_EQ(best.size(), 12u);
  for (size_t g = 1; g < best.size(); ++g) EXPECT_GE(std::stod(best[g]), std::stod(best[g - 1]));
  // The best of generation 11 is the best of all evaluated individuals.
  EXPECT_EQ(Rows(db, "SELECT MAX(fitness) FROM individuals")[0], best.back());

  // The CLI reads it back, through the embedded read-only coordinator on the file.
  const std::string cli = Bin("gaitforge") + " --db " + db + " ";
  auto hof = RunCommand(cli + "hof " + id + " --generation 5 --json");
  EXPECT_EQ(hof.exit_code, 0) << hof.err;
  EXPECT_NE(hof.out.find("\"generation\":5"), std::string::npos) << hof.out;
  auto history = RunCommand(cli + "history " + id + " --csv");
  EXPECT_EQ(history.exit_code, 0) << history.err;
  EXPECT_EQ(std::count(history.out.begin(), history.out.end(), '\n'), 13);
  auto list = RunCommand(cli + "list --json");
  EXPECT_NE(list.out.find(id), std::string::npos);
  // --version is the build identity the workers reported (pinned as the study's sim_build).
  auto version = RunCommand(Bin("gaitforge") + " --version");
  EXPECT_EQ(version.exit_code, 0);
  ASSERT_FALSE(version.out.empty());
  EXPECT_NE(list.out.find("\"sim_build\":\"" + version.out.substr(0, version.out.size() - 1) +
                          "\""),
            std::string::npos)
      << version.out << list.out;
  EXPECT_EQ(RunCommand(cli + "show nope").exit_code, 3);
  EXPECT_EQ(RunCommand(cli + "hof " + id + " --generation 12").exit_code, 3);
}

TEST(EndToEnd, OneWorkerAndThreeWorkersGiveTheSameStudy) {
  TempDir a, b;
  const std::string db1 = a.File("one.db"), db3 = b.File("three.db");
  ASSERT_FALSE(RunStudy(a, db1, 1).empty());
  ASSERT_FALSE(RunStudy(b, db3, 3).empty());
  const std::string q =
      "SELECT generation, member, hex(genes), valid, fitness, carried FROM individuals "
      "ORDER BY generation, member";
  EXPECT_EQ(Rows(db1, q), Rows(db3, q));
  const std::string h = "SELECT generation, rank, hex(genes), fitness FROM hall_of_fame "
                        "ORDER BY generation, rank";
  EXPECT_EQ(Rows(db1, h), Rows(db3, h));
  EXPECT_EQ(Rows(db1, "SELECT hex(engine_state) FROM generations ORDER BY generation"),
            Rows(db3, "SELECT hex(engine_state) FROM generations ORDER BY generation"));
  // The work really was spread (fair shares of each generation among the workers seen).
  EXPECT_GE(std::stoi(Rows(db3, "SELECT COUNT(DISTINCT worker_id) FROM individuals "
                                "WHERE carried = 0")[0]),
            2);
}

TEST(EndToEnd, TheCoordinatorServesGrpcHealth) {
  TempDir dir;
  LocalCluster cluster(dir.path(), dir.File("r.db"));
  ASSERT_TRUE(cluster.ok());
  auto stub = grpc::health::v1::Health::NewStub(cli::MakeChannel(cluster.target()));
  grpc::ClientContext ctx;
  cli::SetDeadline(ctx, 10);
  grpc::health::v1::HealthCheckRequest req;
  grpc::health::v1::HealthCheckResponse resp;
  grpc::Status s = stub->Check(&ctx, req, &resp);
  ASSERT_TRUE(s.ok()) << s.error_message();
  EXPECT_EQ(resp.status(), grpc::health::v1::HealthCheckResponse::SERVING);
}

TEST(EndToEnd, OneWritingCoordinatorPerDatabase) {
  TempDir dir;
  LocalCluster first(dir.path(), dir.File("r.db"));
  ASSERT_TRUE(first.ok());
  auto second = RunCommand(Bin("gaitforge-coordinator") + " --listen 127.0.0.1:0 --db " +
                           dir.File("r.db"));
  EXPECT_EQ(second.exit_code, 2);
  EXPECT_NE(second.err.find("is in use by another coordinator"), std::string::npos)
      << second.err;
  // Readers are welcome: the CLI's embedded read-only coordinator still answers.
  auto list = RunCommand(Bin("gaitforge") + " --db " + dir.File("r.db") + " list");
  EXPECT_EQ(list.exit_code, 0) << list.err;
  // A writing command talks to the coordinator that holds the database (on loopback).
  auto cancel = RunCommand(Bin("gaitforge") + " --db " + dir.File("r.db") + " cancel x");
  EXPECT_EQ(cancel.exit_code, 3) << cancel.err;
  EXPECT_NE(cancel.err.find("using the coordinator that holds " + dir.File("r.db") + " (pid "),
            std::string::npos)
      << cancel.err;
  EXPECT_NE(cancel.err.find("no study or diagnosis with id 'x'"), std::string::npos) << cancel.err;
}

TEST(EndToEnd, BadInputGetsClearErrorsAndExitCodes) {
  TempDir dir;
  LocalCluster cluster(dir.path(), dir.File("r.db"));
  ASSERT_TRUE(cluster.ok());
  WriteFile(dir.File("bad.yaml"), "seed: 1\npopulation: 5\ngenerations: 2\nobjective:\n"
                                  "  name: analytic.sphere\nmutation: 0.5\n");
  auto r = cluster.Cli("submit " + dir.File("bad.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.yaml:6:1: field 'mutation': unknown field 'mutation'"),
            std::string::npos)
      << r.err;
  WriteFile(dir.File("range.yaml"), "population: 5\ngenerations: 2\nobjective:\n"
                                    "  name: analytic.sphere\n");
  r = cluster.Cli("submit " + dir.File("range.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("range.yaml: field 'ga.elite' = 10 is out of range [0, population - 1 = 4]"),
            std::string::npos)
      << r.err;
  r = cluster.Cli("submit " + dir.File("missing.yaml"));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("missing.yaml"), std::string::npos);
  r = cluster.Cli("show no-such-study");
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_NE(r.err.find("no study with id 'no-such-study'"), std::string::npos) << r.err;
  r = cluster.Cli("list --json");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.out.find("study_id"), std::string::npos) << "nothing was stored: " << r.out;
  r = RunCommand(Bin("gaitforge") + " --coordinator 127.0.0.1:1 --timeout 2 list");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_EQ(RunCommand(Bin("gaitforge") + " frobnicate").exit_code, 2);
  EXPECT_EQ(RunCommand(Bin("gaitforge") + " --help").exit_code, 0);
  EXPECT_EQ(RunCommand(Bin("gaitforge-worker") + " --help").exit_code, 0);
  EXPECT_EQ(RunCommand(Bin("gaitforge-coordinator") + " --help").exit_code, 0);
  EXPECT_EQ(RunCommand(Bin("gaitforge-worker") + " --threads 0").exit_code, 2);
}

TEST(EndToEnd, LocalRunsTheEmbeddedDefaultAndLeavesItQueryable) {
  TempDir dir;
  WriteFile(dir.File("spec.yaml"), kSpec);
  auto r = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " local spec.yaml " +
                      "--workers 2 --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir.File("runs/gaitforge.db")));
  // The fitness figure, drawn by matplotlib.
  int svgs = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.File("runs/plots"))) {
    if (e.path().string().ends_with("-fitness.svg")) {
      ++svgs;
      EXPECT_NE(ReadFile(e.path().string()).find("<svg"), std::string::npos);
    }
  }
  EXPECT_EQ(svgs, 1);
  auto list = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " list");
  EXPECT_EQ(list.exit_code, 0) << list.err;
  EXPECT_NE(list.out.find("completed"), std::string::npos) << list.out;
}

// Genes marked log: true through the CLI, the coordinator, the workers and the store: the
// first generation centres on the range's geometric middle (0.032; a linear search's
// would be 0.5), and the fit is reported in the genes' units.
TEST(EndToEnd, LogGenesAreSearchedByTheirLogarithmAndReportedInUnits) {
  TempDir dir;
  WriteFile(dir.File("log.yaml"),
            "name: log\nseed: 5\nengine: cmaes\npopulation: 12\ngenerations: 60\n"
            "objective: {name: analytic.sphere}\n"
            "bounds:\n  - {name: a, lo: 0.001, hi: 1, log: true}\n"
            "  - {name: b, lo: 0.001, hi: 1, log: true}\n"
            "cmaes: {max_evaluations: 600, restarts: none}\n");
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge") + " --db log.db ";
  auto r = RunCommand(cli + "local log.yaml --workers 2 --dashboard off");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::smatch m;
  const std::string list = RunCommand(cli + "list --json").out;
  ASSERT_TRUE(std::regex_search(list, m, std::regex(R"re("study_id":\s*"([^"]+)")re"))) << list;
  const std::string id = m[1].str();
  const std::string first = RunCommand(cli + "individuals " + id + " --generation 0 --json").out;
  std::vector<double> sampled;
  const std::regex pair(R"re("genes":\s*\[([-+0-9.eE]+),\s*([-+0-9.eE]+)\])re");
  for (auto it = std::sregex_iterator(first.begin(), first.end(), pair);
       it != std::sregex_iterator(); ++it)
    for (int g = 1; g <= 2; ++g) sampled.push_back(std::stod((*it)[g].str()));
  ASSERT_EQ(sampled.size(), 24u) << first;
  std::sort(sampled.begin(), sampled.end());
  EXPECT_GE(sampled.front(), 0.001);
  EXPECT_LE(sampled.back(), 1.0);
  // Centred on the geometric middle (0.032), not the linear one (0.5).
  EXPECT_LT(sampled[12], 0.1) << first;
  // The sphere's optimum in units: 0.6 and 0.4 of each range (workers/objectives/analytic.cc).
  const std::string hof = RunCommand(cli + "hof " + id + " --json").out;
  ASSERT_TRUE(std::regex_search(hof, m, pair)) << hof;
  EXPECT_NEAR(std::stod(m[1].str()), 0.001 + 0.6 * 0.999, 0.01) << hof;
  EXPECT_NEAR(std::stod(m[2].str()), 0.001 + 0.4 * 0.999, 0.01) << hof;
}

// The private coordinator and workers of `gaitforge local` die with it however it ends
// (here kill -9): nothing is left holding the database, `resume` finishes the study, and
// the result is the one an uninterrupted run gives.
TEST(EndToEnd, AKilledLocalCommandLeavesNoOrphansAndResumesToTheSameStudy) {
  TempDir dir;
  WriteFile(dir.File("spec.yaml"), "name: orphan\nseed: 7\npopulation: 40\ngenerations: 100\n"
                                   "objective:\n  name: analytic.rastrigin\n"
                                   "  params: {work_us: 5000}\n");
  const std::string killed = dir.File("killed.db"), whole = dir.File("whole.db");
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge") + " --db ";
  RunCommand("cd " + dir.path() + " && { " + Bin("gaitforge") + " --db " + killed +
             " local spec.yaml --workers 2 > local.out 2> local.err & echo $! > local.pid; }");
  const std::string pid = std::to_string(std::stoi(ReadFile(dir.File("local.pid"))));
  // Wait until generations are stored (a read-only coordinator answers beside the writer).
  const std::string id = WaitForGenerations(cli + killed, 3);
  ASSERT_FALSE(id.empty()) << ReadFile(dir.File("local.err"));
  ASSERT_EQ(RunCommand("kill -9 " + pid).exit_code, 0);
  // Its coordinator (the only process with this database on its command line) and workers
  // (ids local-I-PID) get SIGTERM from the kernel and exit.
  // (The pattern is read from a file so that the shell running pgrep does not match it.)
  WriteFile(dir.File("orphans.re"), killed + "|local-[0-9]+-" + pid + "( |$)");
  const std::string orphans = "pgrep -f -- \"$(cat " + dir.File("orphans.re") + ")\"";
  bool gone = false;
  for (int i = 0; i < 600 && !gone; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    gone = RunCommand(orphans).out.empty();
  }
  EXPECT_TRUE(gone) << RunCommand("ps -ef | grep -e " + pid + " -e killed.db").out;
  auto resume = RunCommand(cli + killed + " resume " + id + " --workers 2");
  EXPECT_EQ(resume.exit_code, 0) << resume.err;
  EXPECT_EQ(Rows(killed, "SELECT state, generations_done FROM studies")[0], "completed|100|");

  auto uninterrupted = RunCommand(cli + whole + " local spec.yaml --workers 2");
  ASSERT_EQ(uninterrupted.exit_code, 0) << uninterrupted.err;
  const std::string q =
      "SELECT generation, member, hex(genes), valid, fitness, carried FROM individuals "
      "ORDER BY generation, member";
  EXPECT_EQ(Rows(killed, q), Rows(whole, q));
}

TEST(EndToEnd, CaterpillarStudyRunsInOdeAndReportsThePapersFigures) {
  TempDir dir;
  WriteFile(dir.File("cat.yaml"), "name: cat\nseed: 3\npopulation: 16\ngenerations: 3\n"
                                  "objective: {name: caterpillar.distance}\n"
                                  "ga: {elite: 4}\n");
  auto r = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") +
                      " local cat.yaml --workers 2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string db = dir.File("runs/gaitforge.db");
  // Every evaluation ran the ODE model: its metrics are stored with the result.
  EXPECT_EQ(Rows(db, "SELECT COUNT(DISTINCT member) FROM metrics WHERE name = "
                     "'distance_per_cycle' AND generation = 0")[0],
            "16|");
  EXPECT_EQ(Rows(db, "SELECT COUNT(*) FROM individuals WHERE carried = 0 AND valid = 1 AND "
                     "fitness = (SELECT value FROM metrics m WHERE m.study_id = "
                     "individuals.study_id AND m.generation = individuals.generation AND "
                     "m.member = individuals.member AND m.name = 'distance_per_cycle')")[0],
            Rows(db, "SELECT COUNT(*) FROM individuals WHERE carried = 0 AND valid = 1")[0]);
  // The paper's figures and the best gait's markers.
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(dir.File("runs/plots")))
    files.push_back(e.path().filename().string());
  for (const char* suffix : {"-fitness.svg", "-gaits.svg", "-period-sweep.svg", "-wave.svg",
                             "-best-trajectory.csv", "-report.json"}) {
    EXPECT_EQ(std::count_if(files.begin(), files.end(),
                            [&](const std::string& f) { return f.ends_with(suffix); }),
              1)
        << suffix;
  }
  // Any hall-of-fame member's trajectory, in the recordings' CSV format.
  const std::string id = Rows(db, "SELECT study_id FROM studies")[0];
  auto t = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " trajectory " +
                      id.substr(0, id.size() - 1) + " --rank 2 --rate 50 --cycles 2 " +
                      "--output r2.csv");
  ASSERT_EQ(t.exit_code, 0) << t.err;
  const std::string csv = ReadFile(dir.File("r2.csv"));
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "t,m1.x,m1.y,m1.z,m2.x,m2.y,m2.z,m3.x,m3.y,m3.z,m4.x,m4.y,m4.z,m5.x,m5.y,m5.z,m6.x,"
            "m6.y,m6.z");
  const auto lines = std::count(csv.begin(), csv.end(), '\n');
  EXPECT_GT(lines, 10);
  EXPECT_NE(ReadFile(dir.File("r2.csv.json")).find("\"robot\": \"caterpillar\""),
            std::string::npos);
  auto bad = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " trajectory " +
                        id.substr(0, id.size() - 1) + " --rank 99 --output x.csv");
  EXPECT_EQ(bad.exit_code, 3);
  EXPECT_NE(bad.err.find("--rank = 99 is out of range [0, 3]"), std::string::npos) << bad.err;
}

// The report re-simulates the best gaits with the study's own model: its `set` overrides
// and its timestep, and re-runs each at half and a quarter of that step. With the pistons'
// force set to 0 nothing moves, in the study and in every re-simulation; the model file's
// 8.8 N would move them by millimetres per cycle.
TEST(EndToEnd, CaterpillarReportUsesTheStudysModel) {
  TempDir dir;
  WriteFile(dir.File("still.yaml"),
            "name: still\nseed: 4\npopulation: 8\ngenerations: 1\n"
            "objective: {name: caterpillar.distance, params: {timestep_ms: 0.8},\n"
            "            options: {set: \"actuators.force_n=0\"}}\n"
            "ga: {elite: 3}\n");
  auto r = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") +
                      " local still.yaml --workers 1 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string report;
  for (const auto& e : std::filesystem::directory_iterator(dir.File("runs/plots")))
    if (e.path().string().ends_with("-report.json")) report = ReadFile(e.path().string());
  ASSERT_FALSE(report.empty());
  // Three gaits, each checked at 0.8, 0.4 and 0.2 ms.
  std::map<long, int> steps;  // microseconds x 10 -> count
  const std::string step_key = "\"timestep_s\": ";
  for (size_t at = report.find(step_key); at != std::string::npos;
       at = report.find(step_key, at + 1))
    ++steps[std::lround(1e7 * std::strtod(report.c_str() + at + step_key.size(), nullptr))];
  EXPECT_EQ(steps, (std::map<long, int>{{2000, 3}, {4000, 3}, {8000, 3}}));
  // Every simulated distance in the report (sweeps and checks, not the wave) is ~0.
  const std::string gaits = report.substr(0, report.find("\"wave\""));
  const std::string key = "\"distance_per_cycle_m\": ";
  int distances = 0;
  for (size_t at = gaits.find(key); at != std::string::npos; at = gaits.find(key, at + 1)) {
    const double d = std::strtod(gaits.c_str() + at + key.size(), nullptr);
    EXPECT_LT(std::fabs(d), 1e-4) << gaits.substr(at, 60);
    ++distances;
  }
  EXPECT_EQ(distances, 3 * (13 + 3));
}

}  // namespace
}  // namespace gaitforge::testing
