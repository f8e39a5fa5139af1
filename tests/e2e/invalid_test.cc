// Invalid evaluations never pass in silence: a generation with no valid member stops the
// study with the reason, and invalid members never show a fitness.
#include <gtest/gtest.h>
#include <algorithm>

#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

// All rows of a query, one per line.
std::string Query(const std::string& db, const std::string& sql) {
  std::string out;
  for (const auto& row : Rows(db, sql)) out += row + "\n";
  return out;
}

// Every evaluation of this spec is invalid: the model override cannot be read.
constexpr char kAllInvalid[] =
    "name: inv\nseed: 1\npopulation: 8\ngenerations: 3\n"
    "objective: {name: caterpillar.distance, options: {set: \"nonsense\"}}\nga: {elite: 2}\n";
constexpr char kReason[] = "option set: 'nonsense': expected NAME=NUMBER";

TEST(Invalid, AGenerationWithNoValidMemberStopsTheStudyWithTheReason) {
  TempDir dir;
  WriteFile(dir.File("s.yaml"), kAllInvalid);
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge") + " ";
  auto r = RunCommand(cli + "local s.yaml --workers 1");
  EXPECT_EQ(r.exit_code, 1) << r.err;
  const std::string error = std::string("generation 0: all 8 members are invalid; commonest ") +
                            "reason (8 of 8): " + kReason;
  EXPECT_NE(r.err.find("error: " + error), std::string::npos) << r.err;
  // Stored: the study failed with that error after generation 0, and nothing after it.
  const std::string db = dir.File("runs/gaitforge.db");
  EXPECT_EQ(Query(db, "SELECT state, error, generations_done FROM studies"),
            "failed|" + error + "|1|\n");
  EXPECT_EQ(Query(db, "SELECT COUNT(*), MAX(generation), SUM(valid) FROM individuals"),
            "8|0|0|\n");
  EXPECT_EQ(Query(db, "SELECT generation, invalid FROM generations"), "0|8|\n");
  const std::string id = Query(db, "SELECT study_id FROM studies").substr(0, 10);

  // The hall of fame and the members show "invalid", never the stored 0.
  auto hof = RunCommand(cli + "hof " + id);
  EXPECT_EQ(hof.exit_code, 0) << hof.err;
  EXPECT_NE(hof.out.find("   0     0/0         invalid  "), std::string::npos) << hof.out;
  const auto lines = std::count(hof.out.begin(), hof.out.end(), '\n');
  int invalid = 0;
  for (size_t at = hof.out.find(" invalid "); at != std::string::npos;
       at = hof.out.find(" invalid ", at + 1))
    ++invalid;
  EXPECT_EQ(invalid, lines - 2) << hof.out;  // every entry, after the two header lines
  auto csv = RunCommand(cli + "hof " + id + " --csv");
  EXPECT_NE(csv.out.find("\n0,0,0,,"), std::string::npos) << csv.out;
  auto members = RunCommand(cli + "individuals " + id + " --generation 0");
  EXPECT_NE(members.out.find("\n0,0,,0,"), std::string::npos) << members.out;
  auto show = RunCommand(cli + "show " + id);
  EXPECT_NE(show.out.find("error        " + error), std::string::npos) << show.out;
}

// Periods below the model's 0.05 s are invalid: about half of this space.
std::string SomeInvalidSpec() {
  std::string spec = "name: part\nseed: 1\npopulation: 6\ngenerations: 2\n"
                     "objective: {name: caterpillar.distance}\nga: {elite: 1}\nbounds:\n";
  for (const char* g : {"a_T1", "a_T2", "a_T3", "a_B1", "a_B2", "a_B3", "d_T1", "d_T2", "d_T3",
                        "d_B1", "d_B2", "d_B3"})
    spec += std::string("  - {name: ") + g + ", lo: 0, hi: 1}\n";
  return spec + "  - {name: T, lo: 0.01, hi: 0.07}\n";
}

TEST(Invalid, InvalidMembersAreCountedWithTheirCommonestReasonEverywhere) {
  TempDir dir;
  WriteFile(dir.File("s.yaml"), SomeInvalidSpec());
  LocalCluster cluster(dir.path(), dir.File("r.db"), {"--metrics-listen", "127.0.0.1:0"});
  ASSERT_TRUE(cluster.ok());
  auto submit = cluster.Cli("submit " + dir.File("s.yaml"));
  ASSERT_EQ(submit.exit_code, 0) << submit.err;
  const std::string id = submit.out.substr(0, submit.out.find('\n'));
  cluster.StartWorkers(1);
  auto watch = cluster.Cli("watch " + id + " --json");
  ASSERT_EQ(watch.exit_code, 0) << watch.err;
  // Stored: 3 invalid members in generation 0, 1 in generation 1 (seed 1).
  const std::string db = dir.File("r.db");
  EXPECT_EQ(Query(db, "SELECT generation, invalid FROM generations ORDER BY generation"),
            "0|3|\n1|1|\n");
  EXPECT_EQ(Query(db, "SELECT generation, COUNT(*) FROM individuals WHERE valid = 0 "
                      "GROUP BY generation"),
            "0|3|\n1|1|\n");
  const std::string reason = "gait period T = 0.023532 s is outside [0.05, 10] s";
  // The last progress, `show`, `history` and the metrics say the same.
  EXPECT_NE(watch.out.find("\"invalid\":1,\"invalid_reason\":\"" + reason + "\""),
            std::string::npos)
      << watch.out;
  auto show = cluster.Cli("show " + id);
  EXPECT_NE(show.out.find("invalid      1 in generation 1; commonest reason: " + reason),
            std::string::npos)
      << show.out;
  auto history = cluster.Cli("history " + id + " --csv");
  EXPECT_NE(history.out.find(",6,3,\"gait period T = 0.0307478 s is outside [0.05, 10] s\"\n"),
            std::string::npos)
      << history.out;
  EXPECT_NE(history.out.find(",5,1,\"" + reason + "\"\n"), std::string::npos) << history.out;
  history = cluster.Cli("history " + id);
  EXPECT_NE(history.out.find("INVALID  COMMONEST REASON\n"), std::string::npos) << history.out;
  EXPECT_NE(HttpGet(cluster.metrics_port(), "/metrics")
                .find("gaitforge_study_invalid_members{study=\"" + id + "\"} 1\n"),
            std::string::npos);
}

}  // namespace
}  // namespace gaitforge::testing
