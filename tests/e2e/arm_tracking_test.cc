// Paper 004's tracking end to end: gaitforge-sim track follows the shipped eq. 14 loop with
// the PID alone and with a model's feed-forward, a study (examples/arm-tracking.yaml, the
// real CLI, coordinator and two workers) tunes the PID's gains by ISTE below the paper's,
// and a path without the tracked marker's columns is refused.
#include <regex>
#include <string>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

using ::testing::HasSubstr;

const std::string kExamples = std::string(GAITFORGE_SOURCE_DIR) + "/examples";
const std::string kPath = kExamples + "/recordings/continuum_arm/eq14.csv";
const std::string kPlant = "effect.joint_softening_per_rad=2";

double Field(const std::string& json, const std::string& name) {
  std::smatch m;
  EXPECT_TRUE(std::regex_search(json, m, std::regex("\"" + name + "\": ?([-0-9.eE+]+)"))) << json;
  return m.empty() ? 0 : std::stod(m[1]);
}

std::string Track(const std::string& args) {
  auto r = RunCommand(Bin("gaitforge-sim") + " track --robot continuum_arm --path " + kPath +
                      " --set " + kPlant + " " + args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return r.out;
}

TEST(ArmTracking, TheModelsFeedForwardCutsThePidsErrorOnTheLoop) {
  TempDir dir;
  const std::string pid = Track("--out " + dir.File("pid.csv"));
  const std::string ff = Track("--feedforward model");
  // The paper's gains alone barely bend the arm; the feed-forward does the work.
  EXPECT_GT(Field(pid, "max_error_m"), 0.1);
  EXPECT_LT(Field(ff, "max_error_m"), 0.3 * Field(pid, "max_error_m"));
  EXPECT_LT(Field(ff, "model_rms_error_m"), 1e-3);  // the model follows its own feed-forward
  const std::string ticks = ReadFile(dir.File("pid.csv"));
  EXPECT_THAT(ticks, HasSubstr("t,tip.x.ref,tip.y.ref,tip.x,tip.y,rod1.force,rod2.force,rod3.force\n"));
  EXPECT_THAT(ticks, HasSubstr("\n-2.0000,"));  // the lead-in, then the 20 s loop at 50 Hz
  EXPECT_THAT(ticks, HasSubstr("\n20.0000,"));
}

TEST(ArmTracking, AStudyTunesTheGainsByIsteBelowThePapers) {
  TempDir dir;
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge") + " --db arm.db ";
  auto run = RunCommand(cli + "local " + kExamples + "/arm-tracking.yaml --workers 2 --json");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_THAT(run.out, HasSubstr("STUDY_STATE_COMPLETED"));
  const double best_iste = -Field(run.out, "best");
  const double papers = Field(Track("--feedforward model"), "iste");
  EXPECT_GT(best_iste, 0);
  EXPECT_LT(best_iste, 0.5 * papers) << "the study's best ISTE against the paper's gains'";
  // The report: the path tracked with the descriptor's gains and the best, and its figure.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(run.out, m, std::regex(R"re("study_id":"([^"]+)")re"))) << run.out;
  const std::string plots = dir.File("runs/plots/" + std::string(m[1]));
  EXPECT_NE(ReadFile(plots + "-tracking-0.svg").find("<svg"), std::string::npos);
  const std::string report = ReadFile(plots + "-tracking.json");
  EXPECT_THAT(report, HasSubstr("\"best\": \"tracking.kp="));
  EXPECT_NEAR(Field(report.substr(report.find("\"descriptor\"")), "iste"), papers, 1e-9);
}

TEST(ArmTracking, APathWithoutTheTrackedMarkerIsRefused) {
  TempDir dir;
  WriteFile(dir.File("p.csv"), "t,tip.x,tip.z\n0,0,-0.3\n0.02,0,-0.3\n");
  WriteFile(dir.File("p.csv.json"), R"({"robot": "continuum_arm", "command": {"kind": "path"}})");
  auto r = RunCommand(Bin("gaitforge-sim") + " track --robot continuum_arm --path " + dir.File("p.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("no column 'tip.y', the tracked marker's y"));
  WriteFile(dir.File("p.csv.json"), R"({"robot": "continuum_arm", "command": {"kind": "path", "genes": [1]}})");
  r = RunCommand(Bin("gaitforge-sim") + " track --robot continuum_arm --path " + dir.File("p.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_THAT(r.err, HasSubstr("a path has no genes"));
}

}  // namespace
}  // namespace gaitforge::testing
