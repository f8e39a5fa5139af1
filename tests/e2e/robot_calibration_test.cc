// The fixture robot (tests/fixtures/robots/twobox/, only files) runs the two other study
// kinds through the real CLI, coordinator and workers: a calibration against a recording
// simulated from it with a changed parameter recovers the parameter, and the gap finder
// finds a tether concealed in its recordings (a reduced configuration: a few fits).
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

using ::testing::HasSubstr;

std::string Fixture() { return std::string(GAITFORGE_SOURCE_DIR) + "/tests/fixtures/robots/twobox"; }

// A recording of the fixture robot's gait `genes` simulated with `set`, at dir/name.
void Record(const TempDir& dir, const std::string& name, const std::string& genes,
            const std::string& set) {
  auto r = RunCommand(Bin("gaitforge-sim") + " trajectory --robot " + Fixture() +
                      "/robot.yaml --genes " + genes + " --settle 0 --cycles 6 --set " + set +
                      " --out " + dir.File(name));
  ASSERT_EQ(r.exit_code, 0) << r.err;
}

// The diagnosis tests' recordings a.csv, b.csv (training) and c.csv (held out), with `set`.
void RecordThreeGaits(const TempDir& dir, const std::string& set) {
  Record(dir, "a.csv", "2,0.6,0.2,0.25", set);
  Record(dir, "b.csv", "1.5,0.5,-0.1,0", set);
  Record(dir, "c.csv", "2.5,0.4,0.1,0.5", set);
}

// `gaitforge diagnose` of the fixture robot on dir's a.csv, b.csv (training) and c.csv
// (held out) over three candidates at small budgets, the spec's `extra` lines appended.
CommandResult Diagnose(const TempDir& dir, const std::string& name, const std::string& extra) {
  WriteFile(dir.File("d.yaml"),
            "name: " + name + "\nseed: 2\nrobot: " + Fixture() +
                "/robot.yaml\ntraining: [a.csv, b.csv]\nheld_out: [c.csv]\n"
                "candidates: [tether.constant, friction.viscous, actuator.delay]\n"
                "base_parameters: [{name: hinge.stiffness_nm_per_rad, lo: 0.02, hi: 0.1}]\n"
                "time_offset_range_s: 0\nscreening_evaluations: 24\nfull_evaluations: 64\n"
                "top: 2\ntry_pairs: false\n" +
                extra);
  return RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") +
                    " --db d.db --out out diagnose d.yaml --json --workers 2");
}

TEST(RobotStudy, AFixtureRobotIsCalibratedFromARecordingOfAChangedParameter) {
  TempDir dir;
  Record(dir, "stiff.csv", "2,0.6,0.2,0.25", "hinge.stiffness_nm_per_rad=0.2");
  EXPECT_THAT(ReadFile(dir.File("stiff.csv")), HasSubstr("t,hinge.angle,tail.x,tail.z"));
  const std::string spec = "name: twobox-cal\nseed: 1\nengine: cmaes\npopulation: 8\n"
                           "generations: 12\nobjective:\n  name: robot.calibration\n  robot: " +
                           Fixture() + "\n  recordings: [stiff.csv]\nbounds:\n"
                           "  - {name: hinge.stiffness_nm_per_rad, lo: 0.01, hi: 1}\n";
  WriteFile(dir.File("cal.yaml"), spec);
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge") + " --db cal.db";
  auto run = RunCommand(cli + " local cal.yaml --workers 2");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  std::smatch m;
  const std::string list = RunCommand(cli + " list --json").out;
  ASSERT_TRUE(std::regex_search(list, m, std::regex(R"re("study_id":\s*"([^"]+)")re"))) << list;
  auto hof = RunCommand(cli + " hof " + m[1].str() + " --json");
  ASSERT_EQ(hof.exit_code, 0) << hof.err;
  ASSERT_TRUE(std::regex_search(hof.out, m, std::regex(R"("genes":\s*\[([-0-9.e]+)\])"))) << hof.out;
  EXPECT_NEAR(std::stod(m[1]), 0.2, 0.01) << hof.out;  // the nominal 0.05 is far off

  // A calibration gene the robot does not have is refused, naming the nearest.
  WriteFile(dir.File("bad.yaml"), std::regex_replace(spec, std::regex("hinge.stiffness_nm_per_rad"),
                                                     "hinge.stifness_nm_per_rad"));
  auto bad = RunCommand(cli + " local bad.yaml --workers 1");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_THAT(bad.err, HasSubstr("bad.yaml:11:6: field 'bounds[0].name' 'hinge.stifness_nm_per_rad' is not a "
                                 "calibratable parameter of the twobox; nearest: "
                                 "hinge.stiffness_nm_per_rad"));
}

TEST(RobotStudy, TheGapFinderFindsATetherConcealedInTheFixtureRobotsRecordings) {
  TempDir dir;
  const std::string hose = "effect.tether_force_n=0.2";
  RecordThreeGaits(dir, hose);
  auto r = Diagnose(dir, "twobox-hose", "");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_NE(r.out.find(R"("verdict": "found", "effects": [{"id": "tether.constant")"),
            std::string::npos)
      << r.out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m,
                                std::regex(R"re("effect.tether_force_n": \{"index": 1, "value": ([-0-9.e]+))re")))
      << r.out;
  EXPECT_NEAR(std::stod(m[1]), 0.2, 0.03);
  // Where the mismatch lives: the fixture's own markers (tail, nose) sliced.
  EXPECT_THAT(r.out, ::testing::Not(HasSubstr(R"("located": {})"))) << r.out;
  EXPECT_THAT(r.out, HasSubstr("tail"));
  // The corrected model names the robot's descriptor, written beside it.
  EXPECT_THAT(r.out, HasSubstr("corrected-model.yaml"));

  // Closing the loop: a robust gait study from the diagnosis evolves on the corrected
  // model over the tether's fitted range, and its hall of fame predicts with an interval.
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge") + " --db d.db";
  const std::string listed = RunCommand(cli + " diagnoses --json").out;
  ASSERT_TRUE(std::regex_search(listed, m, std::regex(R"re("diagnosis_id":\s*"([^"]+)")re"))) << listed;
  WriteFile(dir.File("g.yaml"), "name: twobox-robust\nseed: 1\npopulation: 6\ngenerations: 2\n"
                                "ga: {elite: 2}\nobjective:\n  name: robot.distance\n  robot: " +
                                    Fixture() + "\n  from_diagnosis: " + m[1].str() +
                                    "\n  robust: {members: 4}\n");
  auto g = RunCommand(cli + " local g.yaml --workers 2 --dashboard off");
  ASSERT_EQ(g.exit_code, 0) << g.err;
  const std::string studies = RunCommand(cli + " list --json").out;
  ASSERT_TRUE(std::regex_search(studies, m, std::regex(R"re("study_id":\s*"(twobox-robust[^"]*)")re"))) << studies;
  const std::string show = RunCommand(cli + " show " + m[1].str() + " --json").out;
  EXPECT_THAT(show, HasSubstr("effect.tether_force_n="));  // the corrected model's set
  EXPECT_TRUE(std::regex_search(show, std::regex(R"re("parameters":\s*\[[^\]]*\{"name":\s*"effect.tether_force_n","lo")re")))
      << show;
  EXPECT_THAT(RunCommand(cli + " hof " + m[1].str()).out, HasSubstr("PREDICTED [MIN, MAX]"));
  // A diagnosis that does not exist is refused, naming the field.
  WriteFile(dir.File("none.yaml"), std::regex_replace(ReadFile(dir.File("g.yaml")),
                                                      std::regex("from_diagnosis: .*"),
                                                      "from_diagnosis: no-such-diagnosis"));
  auto none = RunCommand(cli + " local none.yaml --workers 1 --dashboard off");
  EXPECT_EQ(none.exit_code, 3) << none.err;
  EXPECT_THAT(none.err, HasSubstr("objective.from_diagnosis: no diagnosis with id 'no-such-diagnosis'"));
}

// Blanks every 17th sample of `column` in the recording at `path`, alternately empty and
// NaN (a marker occluded at times: missing samples the parser bridges).
void Occlude(const std::string& path, int column) {
  std::istringstream in(ReadFile(path));
  std::string out, line;
  for (int row = 0; std::getline(in, line); ++row) {
    if (row > 0 && row % 17 == 0) {
      std::vector<std::string> cells = absl::StrSplit(line, ',');
      cells[column] = row % 34 == 0 ? "" : "NaN";
      line = absl::StrJoin(cells, ",");
    }
    out += line + "\n";
  }
  WriteFile(path, out);
}

// The gap finder's honesty on a null: recordings with nothing concealed, made by a finer
// step than the model's (0.25 ms against 1 ms: numerics the model does not share), with a
// stiffness the baseline must fit and a marker occluded at times. At the model's own step
// the candidates come close to the held-out rule (a delay cut 13% of the 15% it asks), as
// the walker's null-1 did (tests/diagnosis/robots/README.md); with numerics first the
// diagnosis moves to a finer step and every candidate fails a test (session 36: with the
// time shift refined within a sample, 0.75 ms instead of 0.25, and the two refitted
// runners-up fail on the held-out recordings rather than the training ones). The caterpillar's
// null cases, made by a reference rig, are the benchmark (tests/diagnosis/README.md).
TEST(RobotStudy, TheGapFinderStaysSilentOnANullRecordedByFinerNumerics) {
  TempDir dir;
  const std::string rig = "simulation.timestep_s=0.00025,hinge.stiffness_nm_per_rad=0.06";
  RecordThreeGaits(dir, rig);
  for (const char* f : {"a.csv", "b.csv", "c.csv"}) Occlude(dir.File(f), 2);
  auto r = Diagnose(dir, "twobox-null", "numerics: first\n");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, HasSubstr(R"("verdict": "none")")) << r.out;
  // Numerics first moved the model to a finer step than its own 1 ms.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"re("numerics": \{"from_ms": 1, "at_ms": ([0-9.]+))re")))
      << r.out;
  EXPECT_LT(std::stod(m[1]), 1.0) << r.out;
  // The refitted runners-up each say why they lost, with a test they failed.
  std::string rest = r.out;
  int refused = 0;
  const std::regex why(R"re("why_not": "(fits the training data|cuts the held-out error|a fitted parameter))re");
  for (; std::regex_search(rest, m, why); rest = m.suffix()) ++refused;
  EXPECT_EQ(refused, 2) << r.out;
}

}  // namespace
}  // namespace gaitforge::testing
