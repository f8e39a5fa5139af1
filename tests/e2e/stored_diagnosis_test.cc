// A diagnosis is a stored job: the coordinator runs it, it outlives the client that asked
// for it, and it is listed and queried over gRPC (docs/diagnosis.md, "Stored diagnoses").
#include <gtest/gtest.h>

#include <chrono>
#include <regex>
#include <string>
#include <thread>

#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

std::string Spec(const std::string& cases) {
  return "name: kept\nseed: 3\ntraining: [" + cases + "train/gait-a.csv, " + cases +
         "train/gait-b.csv]\nheld_out: [" + cases +
         "held_out/gait-c.csv]\ncandidates: [tether.constant, ground.slope]\n"
         "screening_evaluations: 16\nfull_evaluations: 24\ntop: 2\ntry_pairs: false\n";
}

TEST(StoredDiagnosis, OutlivesItsClientAndIsListedAndQueried) {
  TempDir dir;
  LocalCluster cluster(dir.path(), dir.File("d.db"));
  ASSERT_TRUE(cluster.ok());
  cluster.StartWorkers(2);
  WriteFile(dir.File("d.yaml"),
            Spec(std::string(GAITFORGE_SOURCE_DIR) + "/tests/diagnosis/cases/tether-hose/"));
  // The client that asks for it is killed as soon as the diagnosis exists.
  RunCommand("cd " + dir.path() + " && { " + Bin("gaitforge") + " --coordinator " +
             cluster.target() + " diagnose d.yaml --json > c.out 2> c.err & echo $! > c.pid; }");
  std::string id;
  for (int i = 0; i < 600 && id.empty(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::smatch m;
    const std::string listed = cluster.Cli("diagnoses --json").out;
    if (std::regex_search(listed, m, std::regex(R"re("diagnosis_id":"([^"]+)")re"))) id = m[1];
  }
  ASSERT_FALSE(id.empty()) << ReadFile(dir.File("c.err"));
  RunCommand("kill -9 " + ReadFile(dir.File("c.pid")));

  // It runs on: `diagnosis ID` waits for it and prints its report; the files come along.
  auto r = cluster.Cli("--out " + dir.File("got") + " diagnosis " + id + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(R"("verdict": "found", "effects": [{"id": "tether.constant")"),
            std::string::npos)
      << r.out;
  EXPECT_NE(ReadFile(dir.File("got/kept-diagnosis/diagnosis.json")).find("\"verdict\""),
            std::string::npos);
  EXPECT_NE(ReadFile(dir.File("got/kept-diagnosis/diagnosis.svg")).find("<svg"),
            std::string::npos);
  EXPECT_NE(ReadFile(dir.File("got/kept-diagnosis/corrected-model.yaml")).find("tether"),
            std::string::npos);
  // Listed as completed with its verdict; in words, the files named where they were copied.
  const std::string listed = cluster.Cli("diagnoses --json").out;
  EXPECT_NE(listed.find("DIAGNOSIS_STATE_COMPLETED"), std::string::npos) << listed;
  EXPECT_NE(listed.find(R"("verdict":"found")"), std::string::npos) << listed;
  auto words = cluster.Cli("--out " + dir.File("w") + " diagnosis " + id);
  ASSERT_EQ(words.exit_code, 0) << words.err;
  EXPECT_NE(words.out.find("diagnosis kept: found tether.constant"), std::string::npos)
      << words.out;
  EXPECT_NE(words.out.find("report: " + dir.File("w") + "/kept-diagnosis/diagnosis.json"),
            std::string::npos)
      << words.out;
  // The same spec again is the same diagnosis, not a second run.
  auto again = cluster.Cli("--out " + dir.File("again") + " diagnose " + dir.File("d.yaml") +
                           " --json");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ(again.out, r.out);
  EXPECT_EQ(cluster.Cli("diagnosis nothing-here").exit_code, 3);
}

// `cancel ID` stops a running diagnosis and the fits it started; its client exits 1.
TEST(StoredDiagnosis, CancelStopsItAndItsFits) {
  TempDir dir;
  LocalCluster cluster(dir.path(), dir.File("d.db"));
  ASSERT_TRUE(cluster.ok());
  cluster.StartWorkers(1);
  std::string spec =
      Spec(std::string(GAITFORGE_SOURCE_DIR) + "/tests/diagnosis/cases/tether-hose/");
  spec = std::regex_replace(spec, std::regex("full_evaluations: 24"), "full_evaluations: 4000");
  WriteFile(dir.File("d.yaml"), spec);
  // The whole background subshell away from RunCommand's pipe, which it would hold open.
  RunCommand("(cd " + dir.path() + " && { " + Bin("gaitforge") + " --coordinator " +
             cluster.target() +
             " diagnose d.yaml > c.out 2> c.err; echo $? > c.code; }) > /dev/null 2>&1 &");
  std::string id;
  bool fitting = false;
  for (int i = 0; i < 600 && !fitting; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    std::smatch m;
    const std::string listed = cluster.Cli("diagnoses --json").out;
    if (std::regex_search(listed, m, std::regex(R"re("diagnosis_id":"([^"]+)")re"))) id = m[1];
    fitting = cluster.Cli("list --json").out.find("STUDY_STATE_RUNNING") != std::string::npos;
  }
  ASSERT_TRUE(fitting && !id.empty()) << ReadFile(dir.File("c.err"));
  auto c = cluster.Cli("cancel " + id);
  ASSERT_EQ(c.exit_code, 0) << c.err;
  std::string state;
  for (int i = 0; i < 300 && state.find("CANCELLED") == std::string::npos; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    state = cluster.Cli("diagnoses --json").out;
  }
  EXPECT_NE(state.find("DIAGNOSIS_STATE_CANCELLED"), std::string::npos) << state;
  EXPECT_EQ(cluster.Cli("list --json").out.find("STUDY_STATE_RUNNING"), std::string::npos);
  for (int i = 0; i < 100 && ReadFile(dir.File("c.code")).empty(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(ReadFile(dir.File("c.code")), "1\n") << ReadFile(dir.File("c.err"));
  EXPECT_NE(ReadFile(dir.File("c.err")).find("cancelled"), std::string::npos);
  // An id that is neither a study nor a diagnosis.
  auto none = cluster.Cli("cancel nothing-here");
  EXPECT_EQ(none.exit_code, 3);
  EXPECT_NE(none.err.find("no study or diagnosis with id 'nothing-here'"), std::string::npos)
      << none.err;
}

}  // namespace
}  // namespace gaitforge::testing
