// The papers' legged robots through the real CLI, coordinator and workers, on small
// budgets. Paper 001's study (examples/walker-sweep.yaml): a grid over gait and body genes,
// then Nelder-Mead, with its constraints; the result ignores the worker count; body genes
// that are not the robot's parameters, or leave their ranges, are refused before anything
// starts. Paper 003's CPG walk (examples/tigrillo-walk.yaml) by CMA-ES on its calibrated
// model; paper 002's trot (examples/go2-trot.yaml) through its stance controller.
#include <algorithm>
#include <filesystem>
#include <regex>
#include <string>
#include <utility>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

// The example with a 2 x 2 x 1 x 1 x 2 x 1 grid and short searches.
std::string SmallSweep() {
  std::string text = ReadFile(std::string(GAITFORGE_SOURCE_DIR) + "/examples/walker-sweep.yaml");
  text = std::regex_replace(text, std::regex(R"(points_per_axis: \[[^\]]*\])"),
                            "points_per_axis: [2, 2, 1, 1, 2, 1]");
  text = std::regex_replace(text, std::regex(R"(nm_max_iterations: \d+)"), "nm_max_iterations: 2");
  return std::regex_replace(text, std::regex(R"(top_k: \d+)"), "top_k: 2");
}

std::string RunSweep(const TempDir& dir, const std::string& db, int workers) {
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge") + " --db " + db;
  auto r = RunCommand(cli + " local spec.yaml --workers " + std::to_string(workers));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("sweep: the grid is done"));
  auto list = RunCommand(cli + " list --json");
  std::smatch m;
  EXPECT_TRUE(std::regex_search(list.out, m, std::regex(R"re("study_id":"([^"]+)")re")));
  // Paper 001's figures: the grid as a heat map with the searches' path.
  EXPECT_THAT(r.err, HasSubstr("wrote runs/plots/" + m[1].str() + "-sweep.svg"));
  EXPECT_THAT(ReadFile(dir.File("runs/plots/" + m[1].str() + "-sweep.svg")),
              AllOf(HasSubstr("<svg"), HasSubstr("Nelder-Mead points")));
  auto hof = RunCommand(cli + " hof " + m[1].str() + " --json");
  EXPECT_EQ(hof.exit_code, 0) << hof.err;
  return hof.out;
}

TEST(WalkerStudy, PaperOnesSweepOverGaitAndBodyRunsEndToEnd) {
  TempDir dir;
  WriteFile(dir.File("spec.yaml"), SmallSweep());
  const std::string one = RunSweep(dir, "one.db", 1);
  const std::string two = RunSweep(dir, "two.db", 2);
  EXPECT_THAT(one, AllOf(HasSubstr("\"travel\":"), HasSubstr("\"max_tilt_rad\":"),
                         HasSubstr("\"torque_limited_fraction\":"),
                         HasSubstr("\"cost_of_transport\":")));
  // The best genotype holds six genes; its knee stiffness lies in the spec's bounds.
  std::smatch genes;
  ASSERT_TRUE(std::regex_search(one, genes, std::regex(R"re("genes":\[([^\]]*)\])re")));
  const std::string list = genes[1];
  ASSERT_EQ(std::count(list.begin(), list.end(), ','), 5) << list;
  const double knee = std::stod(list.substr(list.rfind(',', list.rfind(',') - 1) + 1));
  EXPECT_GE(knee, 0.1);
  EXPECT_LE(knee, 0.4);
  const std::regex metrics(R"re("metrics":\{[^}]*\})re");
  EXPECT_EQ(std::regex_replace(one, metrics, ""), std::regex_replace(two, metrics, ""));
}

TEST(WalkerStudy, BodyGenesMustBeTheRobotsParametersInTheirRanges) {
  TempDir dir;
  auto run = [&](const std::string& from, const std::string& to) {
    std::string text = SmallSweep();
    text.replace(text.find(from), from.size(), to);
    WriteFile(dir.File("spec.yaml"), text);
    return RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " local spec.yaml --workers 1");
  };
  auto typo = run("knee.stiffness_nm_per_rad", "knee.stifness");
  EXPECT_EQ(typo.exit_code, 2);
  EXPECT_THAT(typo.err, AllOf(HasSubstr("bounds[4].name"), HasSubstr("'knee.stifness'"),
                              HasSubstr("nearest: knee.stiffness_nm_per_rad")));
  auto wide = run("lo: 0.4, hi: 0.8", "lo: 0.4, hi: 20");
  EXPECT_EQ(wide.exit_code, 2);
  EXPECT_THAT(wide.err, AllOf(HasSubstr("bounds[5]"), HasSubstr("ground.friction_coefficient = 20"),
                              HasSubstr("[0, 10]")));
  EXPECT_FALSE(std::filesystem::exists(dir.File("runs/gaitforge.db")));
}

// An example gait study run by `gaitforge local` with 4 members for 2 generations (and the
// extra edits), in `dir`: its hall of fame as JSON.
std::string SmallExampleHof(const TempDir& dir, const std::string& example,
                            const std::vector<std::pair<std::string, std::string>>& edits = {}) {
  std::string text = ReadFile(std::string(GAITFORGE_SOURCE_DIR) + "/examples/" + example);
  text = std::regex_replace(text, std::regex(R"(population: \d+)"), "population: 4");
  text = std::regex_replace(text, std::regex(R"(generations: \d+)"), "generations: 2");
  for (const auto& [from, to] : edits) text = std::regex_replace(text, std::regex(from), to);
  const std::string id = RunLocal(dir, text, "completed after 2 generations");
  return RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " hof " + id + " --json").out;
}

TEST(TigrilloStudy, PaperThreesCpgWalkRunsByCmaesOnTheCalibratedModel) {
  TempDir dir;
  const std::string hof = SmallExampleHof(dir, "tigrillo-walk.yaml");
  EXPECT_THAT(hof, AllOf(HasSubstr("\"distance_per_cycle\":"), HasSubstr("\"max_tilt_rad\":")));
  // The walk's left-right phase stays in its bounds; eight CPG genes.
  std::smatch genes;
  ASSERT_TRUE(std::regex_search(hof, genes, std::regex(R"re("genes":\[([^\]]*)\])re")));
  const std::string list_genes = genes[1];
  EXPECT_EQ(std::count(list_genes.begin(), list_genes.end(), ','), 7) << list_genes;
}

// Paper 002's trot on its Go2 (examples/go2-trot.yaml) on a small budget: the leg_gait
// scheduler and its stance controller, closed on the base's state inside the workers, run
// as a CMA-ES study end to end; the best gait travels forwards, upright.
TEST(Go2Study, PaperTwosTrotRunsByCmaesThroughTheStanceController) {
  TempDir dir;
  const std::string hof = SmallExampleHof(dir, "go2-trot.yaml", {{R"(cycles: \d+)", "cycles: 3"}});
  std::smatch best, tilt;
  ASSERT_TRUE(std::regex_search(hof, best, std::regex(R"re("fitness":([-0-9.e]+))re"))) << hof;
  ASSERT_TRUE(std::regex_search(hof, tilt, std::regex(R"re("max_tilt_rad":([-0-9.e]+))re"))) << hof;
  EXPECT_GT(std::stod(best[1]), 0.02);  // m per 0.6 s cycle: it walks forwards
  EXPECT_LT(std::stod(tilt[1]), 0.35);
  // Its battery's cost of transport (the descriptor's electrical section), stored with the
  // gait: more than the 14 W standby over its 15.5 kg and at most 0.5 m/s.
  std::smatch cot;
  ASSERT_TRUE(
      std::regex_search(hof, cot, std::regex(R"re("electrical_cost_of_transport":([-0-9.e]+))re")))
      << hof;
  EXPECT_GT(std::stod(cot[1]), 14.4 / (15.5 * 9.81 * 0.5));
}

// Paper 002's experiment (examples/go2-experiment.yaml) with short runs: the factorial sweep
// evaluates its 2 gaits x 4 speeds x 4 repeats once each, every run valid with its battery's
// cost of transport, sliding costs under half of trotting at the paper's 0.16 m/s, and the
// statistics report (Welch per speed, two-way ANOVA, box plot) comes with the study.
TEST(Go2Study, PaperTwosExperimentRunsEveryCellOfItsDesignOnce) {
  TempDir dir;
  std::string text = ReadFile(std::string(GAITFORGE_SOURCE_DIR) + "/examples/go2-experiment.yaml");
  text = std::regex_replace(text, std::regex(R"(params: \{cycles: \d+, settle_cycles: \d+\})"),
                            "params: {cycles: 2, settle_cycles: 1}");
  const std::string id = RunLocal(dir, text, "32 evaluations");
  ASSERT_FALSE(id.empty());
  const std::string out = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") +
                                     " individuals " + id + " --generation 0 --json")
                              .out;
  // Per member: its genes (T first, speed fourth) and its cost of transport.
  const std::regex member(
      R"re("genes":\[([0-9.]+),[0-9.]+,[0-9.]+,([0-9.]+),[^\]]*\],"evaluation":\{"valid":true.*?"electrical_cost_of_transport":([0-9.e]+))re");
  double trot = 0, slide = 0;
  int n = 0, slow = 0;
  for (auto it = std::sregex_iterator(out.begin(), out.end(), member); it != std::sregex_iterator();
       ++it, ++n) {
    if (std::stod((*it)[2]) != 0.16) continue;
    ++slow;
    (std::stod((*it)[1]) == 0.6 ? trot : slide) += std::stod((*it)[3]) / 4;
  }
  EXPECT_EQ(n, 32) << out.substr(0, 2000);
  EXPECT_EQ(slow, 8);
  EXPECT_LT(slide, 0.5 * trot) << "trot " << trot << ", slide " << slide;
  // The study's statistics, drawn when it ended: Welch's test per speed, the two-way ANOVA,
  // the box plot (clients/python/gaitforge_factorial.py).
  const std::string stats = ReadFile(dir.File("runs/plots/" + id + "-factorial.json"));
  EXPECT_THAT(stats, HasSubstr("\"metric\": \"electrical_cost_of_transport\""));
  std::smatch welch, gait;
  ASSERT_TRUE(
      std::regex_search(stats, welch, std::regex(R"re("level": "0.16",[^}]*"p": ([-0-9.e]+))re")))
      << stats;
  EXPECT_LT(std::stod(welch[1]), 0.01);  // trot and slide differ at 0.16 m/s
  ASSERT_TRUE(
      std::regex_search(stats, gait, std::regex(R"re("source": "gait",[^}]*"p": ([-0-9.e]+))re")))
      << stats;
  EXPECT_LT(std::stod(gait[1]), 0.001);
  EXPECT_GT(ReadFile(dir.File("runs/plots/" + id + "-factorial.svg")).size(), 1000u);
}

// Paper 003's calibration (examples/tigrillo-calibration.yaml) on a small budget: its
// knee-angle recordings upload, CMA-ES fits the seven parameters within their bounds, and
// the report scores the fit before and after on training and held-out recordings and
// draws the knee angles against the recordings.
TEST(TigrilloStudy, PaperThreesKneeAngleCalibrationRunsAndReports) {
  TempDir dir;
  const std::string examples = std::string(GAITFORGE_SOURCE_DIR) + "/examples";
  std::string text = ReadFile(examples + "/tigrillo-calibration.yaml");
  text = std::regex_replace(text, std::regex(R"(population: \d+)"), "population: 4");
  text = std::regex_replace(text, std::regex(R"(generations: \d+)"), "generations: 1");
  text = std::regex_replace(text, std::regex("recordings/tigrillo/"), examples + "/recordings/tigrillo/");
  WriteFile(dir.File("spec.yaml"), text);
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge");
  // `local` reports a calibration when it completes, as `gaitforge report ID` would.
  auto r = RunCommand(cli + " local spec.yaml --workers 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_THAT(r.out, AllOf(HasSubstr("knee.hind_stiffness_nm_per_rad"), HasSubstr("mass.front_share")));
  auto list = RunCommand(cli + " list --json");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(list.out, m, std::regex(R"re("study_id":"([^"]+)")re")));
  const std::string id = m[1];
  const std::string json = ReadFile(dir.File("runs/plots/" + id + "-calibration.json"));
  for (const char* part : {"\"train_before\"", "\"train_after\"", "\"held_out_before\"", "\"held_out_after\""})
    EXPECT_THAT(json, HasSubstr(part));
  EXPECT_THAT(json, HasSubstr("knee_hl.angle"));
  EXPECT_THAT(ReadFile(dir.File("runs/plots/" + id + "-overlays.svg")), HasSubstr("<svg"));
}

// A knee-angle recording of another robot (the walker's) in the Tigrillo's calibration is
// never compared as if it were the Tigrillo's: the study stops with the reason.
TEST(TigrilloStudy, ARecordingOfAnotherRobotIsRefusedWithTheReason) {
  TempDir dir;
  auto rec = RunCommand(Bin("gaitforge-sim") + " trajectory --robot walker --genes 2,0.4,0,0.1 "
                        "--settle 0 --cycles 4 --rate 50 --out " + dir.File("walker.csv"));
  ASSERT_EQ(rec.exit_code, 0) << rec.err;
  WriteFile(dir.File("spec.yaml"),
            "name: wrong-robot\nseed: 1\nengine: cmaes\npopulation: 4\ngenerations: 2\n"
            "objective:\n  name: robot.calibration\n  robot: tigrillo\n  recordings: [walker.csv]\n"
            "bounds:\n  - {name: knee.front_stiffness_nm_per_rad, lo: 0.1, hi: 1}\n");
  auto r = RunCommand("cd " + dir.path() + " && " + Bin("gaitforge") + " local spec.yaml --workers 1");
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.err, HasSubstr("a recording of robot 'walker', not tigrillo")) << r.err;
}

}  // namespace
}  // namespace gaitforge::testing
