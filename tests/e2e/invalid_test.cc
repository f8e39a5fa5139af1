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
constexpr char kReason[] = "option set: 'nonsense' is not NAME=NUMBER";

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

}  // namespace
}  // namespace gaitforge::testing
