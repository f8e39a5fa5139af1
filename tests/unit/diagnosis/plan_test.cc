// The pure parts of `gaitforge diagnose plan` (services/diagnosis/plan.h): the explanations a
// report leaves, the candidate gaits, the greedy choice and the plan in words.
#include "services/diagnosis/plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

namespace gaitforge::diagnosis::plan {
namespace {

// A report as gaitforge diagnose writes it (report.cc), cut to what a plan reads.
const char* kReport = R"({
  "verdict": "ambiguous",
  "errors": {"baseline_train": 0.004, "train": 0.002},
  "baseline": {"params": {"nuisance.time_offset_s": {"value": 0.01},
                          "joint.stiffness": {"value": 0.5}}, "train": 0.004},
  "effects": [
    {"id": "ground.slope", "train": 0.002, "held_out": 0.0025, "at_bound": [], "delta_bic": -300,
     "params": {"effect.slope_rad": {"value": -0.12}, "joint.stiffness": {"value": 0.52},
                "nuisance.time_offset_s": {"value": 0.02}}}],
  "runners_up": [
    {"id": "ground.slope", "train": 0.002, "held_out": 0.0025, "at_bound": [], "delta_bic": -300,
     "params": {"effect.slope_rad": {"value": -0.12}}},
    {"id": "actuator.lag", "train": 0.0035, "held_out": 0.0031, "at_bound": [], "delta_bic": -20,
     "params": {"effect.actuator_lag_s": {"value": 0.01}}},
    {"id": "tether.growing", "train": 0.0021, "held_out": 0.002, "at_bound": ["effect.k"],
     "delta_bic": -400, "params": {"effect.k": {"value": 50}}},
    {"id": "friction.anisotropic", "train": 0.0024, "held_out": 0.0029, "at_bound": [],
     "delta_bic": -150, "params": {"effect.friction_forward": {"value": 0.3},
                                   "effect.friction_backward": {"value": 0.8}}},
    {"id": "servo.deadband", "train": 0.0041, "held_out": 0.0035, "at_bound": [], "delta_bic": 5,
     "params": {"effect.servo_deadband_rad": {"value": 0.001}}}],
  "resolution": [{"count": "lumps", "from": 5, "at": 10}, {"count": "lumps", "from": 10, "at": 20}],
  "numerics": {"from_ms": 1, "at_ms": 0.5}
})";

TEST(Plan, TheBaselineAndTheFittedRivalsAreTheExplanationsWithoutNuisances) {
  auto e = ExplanationsFromReport(kReport, "r.json", 3);
  ASSERT_TRUE(e.ok()) << e.status();
  ASSERT_EQ(e->size(), 4u);
  EXPECT_EQ((*e)[0].id, "none");
  ASSERT_EQ((*e)[0].set.size(), 1u);  // the time offset belongs to a recording
  EXPECT_EQ((*e)[0].set[0].first, "joint.stiffness");
  EXPECT_DOUBLE_EQ((*e)[0].train, 0.004);
  // The named effect first, then the runners-up closest held out, each once; a fit at a
  // bound and one no better than the baseline on the training data are left out.
  EXPECT_EQ((*e)[1].id, "ground.slope");
  EXPECT_EQ((*e)[1].set.size(), 2u);
  EXPECT_EQ((*e)[2].id, "friction.anisotropic");
  EXPECT_EQ((*e)[3].id, "actuator.lag");
  auto two = ExplanationsFromReport(kReport, "r.json", 1);
  ASSERT_TRUE(two.ok());
  EXPECT_EQ(two->size(), 2u);
}

TEST(Plan, AReportWithNothingFittedBesideTheBaselineIsRefused) {
  auto e = ExplanationsFromReport(
      R"({"errors": {"baseline_train": 0.003}, "effects": [], "runners_up": [
           {"id": "actuator.lag", "held_out": 0.003, "at_bound": [], "delta_bic": 4,
            "params": {}}]})",
      "cases/null-1/diagnosis.json", 3);
  ASSERT_FALSE(e.ok());
  EXPECT_NE(e.status().message().find("cases/null-1/diagnosis.json"), std::string::npos);
  EXPECT_NE(e.status().message().find("nothing for an experiment to separate"), std::string::npos);
  EXPECT_FALSE(ExplanationsFromReport("not json", "x.json", 3).ok());
}

// When a diagnosis plans by itself: undecided, a name to confirm, a mismatch nothing
// explained while a fit beat the baseline on training; never for a none that fits.
TEST(Plan, WhyADiagnosisPlansByItself) {
  std::string r = kReport;
  EXPECT_EQ(WhyPlan(r), PlanReason::kUndecided);
  auto with = [&](const std::string& from, const std::string& to) {
    std::string t = r;
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  const std::string found = with(R"("verdict": "ambiguous")", R"("verdict": "found")");
  EXPECT_EQ(WhyPlan(found), PlanReason::kConfirm);
  EXPECT_EQ(FirstNamed(found), "ground.slope");
  const char* none = R"({"verdict": "none", "unexplained_mismatch": %s, "rule": {"margin": 10},
    "runners_up": [{"id": "joint.damping_growth", "held_out": 0.003, "at_bound": [],
                    "delta_bic": %s}]})";
  auto report = [&](const char* unexplained, const char* dbic) {
    char buf[512];
    std::snprintf(buf, sizeof buf, none, unexplained, dbic);
    return std::string(buf);
  };
  EXPECT_EQ(WhyPlan(report("true", "-0.4")), PlanReason::kUnexplained);
  EXPECT_EQ(WhyPlan(report("false", "-0.4")), PlanReason::kNone);
  EXPECT_EQ(WhyPlan(report("true", "3")), PlanReason::kNone);
  EXPECT_EQ(WhyPlan(report("true", "-30")), PlanReason::kUndecided);
  EXPECT_EQ(WhyPlan("not json"), PlanReason::kNone);
  EXPECT_EQ(FirstNamed(report("true", "-0.4")), "");
}

// How far the recordings a plan was given part the baseline from an explanation: the best
// ratio among the candidates of kind "recorded", in that pair's column.
TEST(Plan, TheRecordedSeparationIsTheBestRecordingsRatioOfThatPair) {
  const char* json = R"({"decisive": 2, "explanations": [{"id": "none"}, {"id": "joint.softening"},
      {"id": "joint.stiffening"}],
    "candidates": [
      {"name": "step-a.csv", "kind": "recorded", "ratio": [0.27, 0.16, 0.3]},
      {"name": "swing.csv", "kind": "recorded", "ratio": [1.05, 1.0, 0.46]},
      {"name": "release.csv, inputs x1.5", "kind": "scaled", "ratio": [8.45, 2.18, 8.58]}]})";
  double decisive = 0;
  EXPECT_DOUBLE_EQ(RecordedSeparation(json, "joint.softening", &decisive), 1.05);
  EXPECT_EQ(decisive, 2);
  EXPECT_DOUBLE_EQ(RecordedSeparation(json, "joint.stiffening"), 1.0);
  EXPECT_TRUE(std::isnan(RecordedSeparation(json, "ground.slope")));
  EXPECT_TRUE(std::isnan(RecordedSeparation("[", "joint.softening")));
}

TEST(Plan, TheReportsModelIsItsLastCountsAndItsStep) {
  auto m = ReportModelOf(kReport, "r.json");
  ASSERT_TRUE(m.ok());
  ASSERT_EQ(m->counts.size(), 1u);
  EXPECT_EQ(m->counts[0], std::make_pair(std::string("lumps"), 20));
  EXPECT_DOUBLE_EQ(m->timestep_ms, 0.5);
}

robots::RobotDescriptor Robot(const std::string& period_gene, double lo, double hi) {
  robots::RobotDescriptor d;
  d.controller.genes = {{period_gene, lo, hi, false}, {"amp", 0, 1, false}, {"phase", 0, 1, true}};
  return d;
}

TEST(Plan, CandidatesAreTheRecordedGaitsVariedAndRandomGaitsInRange) {
  const auto d = Robot("f", 0.5, 3.5);
  const std::vector<Recorded> rec = {{"a.csv", {2.0, 0.4, 0.1}, 4}, {"b.csv", {3.0, 0.2, 0.7}, 5}};
  const auto c = Candidates(d, rec, 5, 7);
  // a: as recorded, longer, period x0.5 (f 4: out of range, left out), x2 (f 1); b: as
  // recorded, longer, period x2 (f 1.5); 5 random.
  ASSERT_EQ(c.size(), 3u + 3u + 5u);
  EXPECT_EQ(c[0].kind, "recorded");
  EXPECT_EQ(c[1].kind, "longer");
  EXPECT_EQ(c[1].cycles, 12);
  EXPECT_EQ(c[2].kind, "period");
  EXPECT_DOUBLE_EQ(c[2].genes[0], 1.0);
  EXPECT_DOUBLE_EQ(c[5].genes[0], 1.5);
  for (size_t k = 6; k < c.size(); ++k) {
    EXPECT_EQ(c[k].kind, "random");
    EXPECT_EQ(c[k].cycles, 5);  // as long as the longest recording
    for (size_t g = 0; g < d.controller.genes.size(); ++g) {
      EXPECT_GE(c[k].genes[g], d.controller.genes[g].lo);
      EXPECT_LT(c[k].genes[g], d.controller.genes[g].hi);
    }
  }
  const auto again = Candidates(d, rec, 5, 7), other = Candidates(d, rec, 5, 8);
  EXPECT_EQ(again.back().genes, c.back().genes);
  EXPECT_NE(other.back().genes, c.back().genes);
  // A period gene T is scaled the other way.
  const auto t = Candidates(Robot("T", 0.5, 4), {{"a.csv", {2.0, 0.4, 0.1}, 4}}, 0, 1);
  ASSERT_EQ(t.size(), 4u);
  EXPECT_DOUBLE_EQ(t[2].genes[0], 1.0);
  EXPECT_DOUBLE_EQ(t[3].genes[0], 4.0);
}

TEST(Plan, APlaybacksCandidatesVaryItsRecordedInputs) {
  const auto c = PlaybackCandidates({"step-a.csv", "swing.csv"});
  ASSERT_EQ(c.size(), 10u);
  EXPECT_EQ(c[0].kind, "recorded");
  EXPECT_EQ(c[0].source, 0);
  EXPECT_DOUBLE_EQ(c[2].inputs.scale, 1.5);
  EXPECT_DOUBLE_EQ(c[3].inputs.time_scale, 2);
  EXPECT_EQ(c[4].kind, "released");
  EXPECT_DOUBLE_EQ(c[4].inputs.release_at, 0.5);
  EXPECT_EQ(c[9].source, 1);
  for (const auto& e : c) EXPECT_TRUE(e.genes.empty());
}

TEST(Plan, TheChoiceCoversThePairsAndStopsWhenNothingMoreHelps) {
  // Pairs: (none, A), (none, B), (A, B). Candidate 3 parts everything but failed once.
  const std::vector<std::vector<double>> ratio = {
      {3.0, 0.5, 0.2}, {0.1, 2.5, 0.4}, {1.0, 1.0, 2.2}, {NAN, 9, 9}, {2.9, 0.4, 0.1}};
  EXPECT_EQ(Choose(ratio, 5, 2), (std::vector<int>{2, 0, 1}));
  EXPECT_EQ(Choose(ratio, 1, 2), (std::vector<int>{2}));
  EXPECT_TRUE(Choose({{0, 0, 0}}, 3, 2).empty());
}

TEST(Plan, InWordsThePlanSaysWhatEachRecordingSeparatesAndWhatStaysOpen) {
  const char* json = R"({"robot": "walker", "residual": 0.002, "decisive": 2,
    "explanations": [{"id": "none"}, {"id": "ground.slope"}, {"id": "friction.anisotropic"}],
    "plan": [{"name": "random gait 3", "genes": {"f": 1.5, "amp": 0.3}, "cycles": 5,
              "period_s": 0.667, "duration_s": 3.33, "ratio": [4.2, 0.3, 2.5]}],
    "pairs": [{"pair": ["none", "ground.slope"], "best_ratio": 4.2, "decided": true},
              {"pair": ["none", "friction.anisotropic"], "best_ratio": 0.3, "decided": false},
              {"pair": ["ground.slope", "friction.anisotropic"], "best_ratio": 2.5, "decided": true}]})";
  auto w = PlanWords(json, "plan.json");
  ASSERT_TRUE(w.ok()) << w.status();
  EXPECT_NE(w->find("1. random gait 3: 5 cycles"), std::string::npos) << *w;
  EXPECT_NE(w->find("amp=0.3 f=1.5"), std::string::npos) << *w;
  EXPECT_NE(w->find("separates none from ground.slope by 4.2x"), std::string::npos) << *w;
  EXPECT_NE(w->find("separates ground.slope from friction.anisotropic by 2.5x"), std::string::npos);
  EXPECT_NE(w->find("no candidate decides: none from friction.anisotropic (best 0.3x)"),
            std::string::npos) << *w;
  EXPECT_NE(w->find("add them to the spec's held_out"), std::string::npos) << *w;
}

}  // namespace
}  // namespace gaitforge::diagnosis::plan
