// `gaitforge diagnose plan` end to end: recordings of the walker made by gaitforge-sim, a
// diagnosis report that leaves a slope as the rival of the baseline, and the plan the CLI
// runs through gaitforge-sim on the real model.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>

#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"
#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

using google::protobuf::Struct;
using google::protobuf::Value;

const Value& At(const Struct& s, const std::string& k) { return s.fields().at(k); }

// Two walker gaits recorded from rest, and a spec that names them.
void MakeCase(const TempDir& dir) {
  for (const auto& [name, genes] : {std::make_pair("a.csv", "2,0.4,0,0.1"),
                                    std::make_pair("b.csv", "1.5,0.3,0.1,0.05")}) {
    auto r = RunCommand(Bin("gaitforge-sim") + " trajectory --robot walker --genes " + genes +
                        " --cycles 3 --settle 0 --rate 50 --out " + dir.File(name));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  WriteFile(dir.File("spec.yaml"),
            "name: plan-test\ntraining: [a.csv]\nheld_out: [b.csv]\ncandidates: [ground.slope]\n");
}

// A report whose only fitted rival of the baseline is a 0.1 rad slope.
const char* kReport = R"({"errors": {"baseline_train": 0.002},
  "baseline": {"params": {}, "train": 0.002}, "effects": [],
  "runners_up": [{"id": "ground.slope", "train": 0.0015, "held_out": 0.0018, "at_bound": [],
                  "delta_bic": -40, "params": {"effect.slope_rad": {"value": 0.1},
                                               "nuisance.time_offset_s": {"value": 0.01}}}]})";

TEST(DiagnosePlan, ProposesTheGaitsThatSeparateTheExplanationsOnTheRealModel) {
  TempDir dir;
  MakeCase(dir);
  WriteFile(dir.File("report.json"), kReport);
  auto r = RunCommand(Bin("gaitforge") + " diagnose plan " + dir.File("spec.yaml") +
                      " --report " + dir.File("report.json") +
                      " --random 3 --propose 2 --workers 2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Struct plan;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &plan).ok()) << r.out;
  EXPECT_EQ(ReadFile(dir.File("plan.json")), r.out);  // written beside the report
  ASSERT_EQ(At(plan, "explanations").list_value().values_size(), 2);
  const auto& candidates = At(plan, "candidates").list_value().values();
  // a, b: as recorded, three times as long, period x0.5 and x2 where f stays in range; 3 random.
  ASSERT_GE(candidates.size(), 7);
  double recorded = -1, longer = -1;
  for (const Value& c : candidates) {
    const Struct& s = c.struct_value();
    ASSERT_TRUE(At(s, "valid").bool_value()) << At(s, "reason").string_value();
    const double sep = At(s, "separation").list_value().values(0).number_value();
    EXPECT_GT(sep, 0) << At(s, "name").string_value();
    if (At(s, "name").string_value() == "a.csv") recorded = sep;
    if (At(s, "name").string_value() == "a.csv, three times as long") longer = sep;
  }
  // A slope pulls the robot back all the time: the longer the run, the farther apart.
  EXPECT_GT(longer, recorded);
  const auto& chosen = At(plan, "plan").list_value().values();
  ASSERT_GE(chosen.size(), 1);
  EXPECT_EQ(At(chosen[0].struct_value(), "genes").struct_value().fields_size(), 4);
  for (const Value& c : chosen)  // what the recordings hold already is never proposed
    EXPECT_NE(At(c.struct_value(), "kind").string_value(), "recorded");
  ASSERT_EQ(At(plan, "pairs").list_value().values_size(), 1);

  r = RunCommand(Bin("gaitforge") + " diagnose plan " + dir.File("spec.yaml") + " --report " +
                 dir.File("report.json") + " --random 0 --propose 1 --output " +
                 dir.File("p.json"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("plan for walker: 1 recording(s) to tell apart none, ground.slope"),
            std::string::npos) << r.out;
  EXPECT_NE(r.out.find("separates none from ground.slope"), std::string::npos) << r.out;
  EXPECT_FALSE(ReadFile(dir.File("p.json")).empty());
}

// Paper 004's arm, driven by recorded rod forces: a plan varies the inputs. A joint that
// softens with its bend parts from the constant one the more, the farther the arm bends.
TEST(DiagnosePlan, VariesAPlaybacksInputsForARobotThatFollowsThem) {
  TempDir dir;
  std::string inputs = "t,rod1.force,rod2.force,rod3.force\n";
  for (int k = 0; k <= 1500; ++k) inputs += std::to_string(k / 1000.0) + ",1.2,1.3,-0.5\n";
  WriteFile(dir.File("in.csv"), inputs);
  auto r = RunCommand(Bin("gaitforge-sim") + " trajectory --robot continuum_arm --inputs " +
                      dir.File("in.csv") + " --rate 100 --out " + dir.File("step.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::filesystem::copy_file(dir.File("step.csv"), dir.File("held.csv"));
  std::filesystem::copy_file(dir.File("step.csv.json"), dir.File("held.csv.json"));
  WriteFile(dir.File("spec.yaml"), "name: arm-plan\ntraining: [step.csv]\nheld_out: [held.csv]\n"
                                   "channels: \"tip.x,tip.y,tip.z\"\n");
  WriteFile(dir.File("report.json"), R"({"errors": {"baseline_train": 0.0005},
    "baseline": {"params": {}, "train": 0.0005}, "effects": [], "runners_up": [
      {"id": "joint.softening", "train": 0.0004, "held_out": 0.0006, "at_bound": [],
       "delta_bic": -30, "params": {"effect.joint_softening_per_rad": {"value": 8}}}]})");
  r = RunCommand(Bin("gaitforge") + " diagnose plan " + dir.File("spec.yaml") + " --report " +
                 dir.File("report.json") + " --workers 2 --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Struct plan;
  ASSERT_TRUE(google::protobuf::util::JsonStringToMessage(r.out, &plan).ok()) << r.out;
  std::map<std::string, double> sep;
  for (const Value& c : At(plan, "candidates").list_value().values()) {
    const Struct& s = c.struct_value();
    ASSERT_TRUE(At(s, "valid").bool_value()) << At(s, "reason").string_value();
    sep[At(s, "name").string_value()] = At(s, "separation").list_value().values(0).number_value();
  }
  ASSERT_EQ(sep.size(), 10u);  // five variants of each of the two recordings
  EXPECT_GT(sep["step.csv, inputs x1.5"], sep["step.csv"]);
  EXPECT_GT(sep["step.csv"], sep["step.csv, inputs x0.5"]);
  EXPECT_GT(sep["step.csv, let go half-way"], 0);
}

TEST(DiagnosePlan, RefusesAReportWithNothingToSeparateAndARequestWithoutAReport) {
  TempDir dir;
  MakeCase(dir);
  WriteFile(dir.File("report.json"),
            R"({"errors": {"baseline_train": 0.002}, "effects": [], "runners_up": []})");
  auto r = RunCommand(Bin("gaitforge") + " diagnose plan " + dir.File("spec.yaml") +
                      " --report " + dir.File("report.json"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("nothing for an experiment to separate"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("report.json"), std::string::npos) << r.err;
  r = RunCommand(Bin("gaitforge") + " diagnose plan " + dir.File("spec.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--report"), std::string::npos) << r.err;
}

// A plan simulates every recording on one model at one rate: a recording of another robot,
// or sampled at another rate, is refused naming the file, not simulated at the wrong rate.
TEST(DiagnosePlan, RefusesRecordingsOfAnotherRobotOrRate) {
  TempDir dir;
  MakeCase(dir);
  WriteFile(dir.File("report.json"), kReport);
  for (const auto& [name, robot, genes, rate] :
       {std::make_tuple("c.csv", "walker", "1.5,0.3,0.1,0.05", "100"),
        std::make_tuple("t.csv", "tigrillo", "1,0.35,0.35,0.1,0.1,0.5,0.25,5", "50")}) {
    auto r = RunCommand(Bin("gaitforge-sim") + " trajectory --robot " + robot + " --genes " +
                        genes + " --cycles 1 --settle 0 --rate " + rate + " --out " +
                        dir.File(name));
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const std::string plan = Bin("gaitforge") + " diagnose plan ";
  const std::string report = " --report " + dir.File("report.json") + " --random 0";
  WriteFile(dir.File("rate.yaml"), "name: p\ntraining: [a.csv]\nheld_out: [c.csv]\n");
  auto r = RunCommand(plan + dir.File("rate.yaml") + report);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("c.csv: sampled every 0.01 s"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("share a rate"), std::string::npos) << r.err;
  WriteFile(dir.File("robot.yaml"), "name: p\ntraining: [a.csv, t.csv]\nheld_out: [b.csv]\n");
  r = RunCommand(plan + dir.File("robot.yaml") + report);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("t.csv: a recording of robot 'tigrillo'"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace gaitforge::testing
