// A diagnosis report in words (services/diagnosis/words.h), from report JSON shaped as
// report.cc writes it.
#include "services/diagnosis/words.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace gaitforge::diagnosis {
namespace {

const char* kFound = R"({"name": "hose", "robot": "caterpillar", "verdict": "found",
 "effects": [{"id": "tether.constant", "params": {
   "nuisance.time_offset_s": {"index": 1, "value": -0.04, "sd": 0.04, "lo": -0.05, "hi": 0.05},
   "effect.tether_force_n": {"index": 0, "value": 1.18, "sd": 1.2, "lo": 0, "hi": 2.5,
                             "range": [0.85, 1.42], "range_share": 0.23}},
   "range_tolerance": 0.0003, "range_evaluations": 33, "range_accepted": 18,
   "train": 0.0005, "held_out": 0.00054, "delta_bic": -5619.9}],
 "errors": {"baseline_train": 0.0033, "baseline_held_out": 0.0018, "noise_floor_held_out": 0.0003},
 "runners_up": [{"id": "ground.slope", "delta_bic": -1731.6, "held_out": 0.00184,
   "at_bound": ["effect.slope_rad"], "why_not": "it absorbs the training mismatch"}],
 "top": 2, "screening_tie": 0, "refitted_singles": 2, "none_reading": "",
 "located": {"summary": "The mismatch lives mainly in forward travel"},
 "located_held_out": {}, "experiment": "", "corrected_model": "out/d/corrected-model.yaml",
 "rule": {"margin": 10, "held_out_gain": 0.15, "paired_t": 2.015}, "dir": "out/d",
 "figures": ["out/d/located.svg", "out/d/diagnosis.svg"]})";

// Locating can fail (recordings it cannot slice): the words then say so instead of
// naming files that were never written.
TEST(ReportWords, NamesTheLocatedFilesOnlyWhenTheyWereWritten) {
  auto found = ReportWords(kFound);
  ASSERT_TRUE(found.ok()) << found.status();
  EXPECT_NE(found->find("by slice: out/d/located.json and located.svg"), std::string::npos) << *found;
  std::string none = kFound;
  none.replace(none.find(R"("located": {"summary": "The mismatch lives mainly in forward travel"})"),
               std::string(R"("located": {"summary": "The mismatch lives mainly in forward travel"})").size(),
               R"("located": {})");
  none.replace(none.find(R"("out/d/located.svg", )"), std::string(R"("out/d/located.svg", )").size(), "");
  auto w = ReportWords(none);
  ASSERT_TRUE(w.ok()) << w.status();
  EXPECT_EQ(w->find("located.json"), std::string::npos) << *w;
  EXPECT_NE(w->find("where the mismatch lives: not located"), std::string::npos) << *w;
}

// A verdict the recordings could not decide ends with the plan the diagnosis kept beside
// its report (plan.json), in words; without one, with the command that makes it. A found
// effect whose rivals lost on their own terms needs none.
TEST(ReportWords, AnUndecidedVerdictEndsWithThePlanOfTheRecordingsThatWouldDecide) {
  auto found = ReportWords(kFound);
  ASSERT_TRUE(found.ok());
  EXPECT_EQ(found->find("would decide"), std::string::npos) << *found;
  std::string ambiguous = kFound;
  const std::string found_verdict = R"("verdict": "found")";
  ambiguous.replace(ambiguous.find(found_verdict), found_verdict.size(),
                    R"("verdict": "ambiguous")");
  const std::string dir = ::testing::TempDir() + "/words-plan";
  std::filesystem::create_directories(dir);
  std::filesystem::remove(dir + "/plan.json");
  auto hint = ReportWords(ambiguous, dir);
  ASSERT_TRUE(hint.ok());
  EXPECT_NE(hint->find("gaitforge diagnose plan SPEC --report " + dir + "/diagnosis.json"),
            std::string::npos) << *hint;
  std::ofstream(dir + "/plan.json") << R"({"robot": "caterpillar", "residual": 0.0005,
    "decisive": 2, "explanations": [{"id": "none"}, {"id": "tether.constant"}],
    "plan": [{"name": "gait-a.csv, three times as long", "genes": {"T": 1.2}, "cycles": 30,
              "period_s": 1.2, "duration_s": 36, "ratio": [5.5]}],
    "pairs": [{"pair": ["none", "tether.constant"], "best_ratio": 5.5, "decided": true}]})";
  auto planned = ReportWords(ambiguous, dir);
  ASSERT_TRUE(planned.ok());
  EXPECT_NE(planned->find("the recordings that would decide (" + dir + "/plan.json):"),
            std::string::npos) << *planned;
  EXPECT_NE(planned->find("1. gait-a.csv, three times as long: 30 cycles"), std::string::npos)
      << *planned;
}

// A found effect with a plan beside it (no recording given parted it from the baseline by
// the decisive level) ends with the recording that would confirm it.
TEST(ReportWords, AFoundEffectThatNoRecordingPartsEndsWithTheRecordingToConfirmIt) {
  const std::string dir = ::testing::TempDir() + "/words-confirm";
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/plan.json") << R"({"robot": "caterpillar", "residual": 0.0005,
    "decisive": 2, "explanations": [{"id": "none"}, {"id": "tether.constant"}],
    "candidates": [{"name": "gait-a.csv", "kind": "recorded", "ratio": [1.2]}],
    "plan": [{"name": "gait-a.csv, three times as long", "genes": {"T": 1.2}, "cycles": 30,
              "period_s": 1.2, "duration_s": 36, "ratio": [5.5]}],
    "pairs": [{"pair": ["none", "tether.constant"], "best_ratio": 5.5, "decided": true}]})";
  auto w = ReportWords(kFound, dir);
  ASSERT_TRUE(w.ok()) << w.status();
  EXPECT_NE(w->find("to confirm tether.constant: no recording given parts it from the model "
                    "without it by more than 1.2 times what the model leaves unexplained (2 "
                    "would decide)"),
            std::string::npos)
      << *w;
  EXPECT_NE(w->find("1. gait-a.csv, three times as long: 30 cycles"), std::string::npos) << *w;
  // A plan that did not fit the named effect (no column to read): no figure is made up.
  std::string other = kFound;
  const std::string id = R"("id": "tether.constant")";
  other.replace(other.find(id), id.size(), R"("id": "tether.growing")");
  auto unread = ReportWords(other, dir);
  ASSERT_TRUE(unread.ok()) << unread.status();
  EXPECT_NE(unread->find("to confirm tether.growing, the recordings that would part it"),
            std::string::npos)
      << *unread;
  EXPECT_EQ(unread->find("nan"), std::string::npos) << *unread;
}

TEST(ReportWords, AFoundEffectWithItsMagnitudesInGeneOrderAndTheRunnersUp) {
  auto w = ReportWords(kFound);
  ASSERT_TRUE(w.ok()) << w.status();
  EXPECT_EQ(w->rfind("diagnosis hose: found tether.constant\n", 0), 0u) << *w;
  const size_t force = w->find("effect.tether_force_n"), offset = w->find("nuisance.time_offset_s");
  ASSERT_NE(force, std::string::npos) << *w;
  EXPECT_LT(force, offset) << "genes in the order fitted";
  EXPECT_NE(w->find("range 0.85 .. 1.42"), std::string::npos) << *w;
  EXPECT_NE(w->find("held-out error 1.8 -> 0.54 mm"), std::string::npos) << *w;
  EXPECT_NE(w->find("where it showed: The mismatch lives mainly in forward travel"),
            std::string::npos);
  EXPECT_NE(w->find("out/d/diagnosis.svg"), std::string::npos);
  EXPECT_NE(w->find("ground.slope (dBIC -1731.6, held-out 1.84 mm, at the edge of its range: "
                    "effect.slope_rad): it absorbs the training mismatch"),
            std::string::npos)
      << *w;
}

TEST(ReportWords, NoneSaysWhatTheRuleAskedAndWhatTheSpreadMeans) {
  auto w = ReportWords(R"({"name": "n", "verdict": "none", "effects": [],
    "errors": {"baseline_held_out": 0.002, "noise_floor_held_out": 0.0004},
    "rule": {"margin": 10, "held_out_gain": 0.15, "paired_t": 2.015},
    "none_reading": "the calibrated model matches within its numeric spread",
    "experiment": "", "runners_up": [], "dir": "o"})");
  ASSERT_TRUE(w.ok()) << w.status();
  EXPECT_NE(w->find("no missing physics found"), std::string::npos) << *w;
  EXPECT_NE(w->find("(2 mm +- 0.4 mm"), std::string::npos) << *w;
  EXPECT_NE(w->find("by 15% with a paired t above 2.015"), std::string::npos) << *w;
  EXPECT_NE(w->find("matches within its numeric spread"), std::string::npos) << *w;
}

// Structure first: the structure fitted into the baseline comes before the effect found
// on top of it, with its own magnitudes; "structure": null says nothing.
TEST(ReportWords, AStructureInTheBaselineIsSaidBeforeTheEffectOnTopOfIt) {
  std::string report = kFound;
  report.insert(report.find("\"effects\""),
                R"("structure": {"id": "friction.anisotropic", "name": "Finite friction",
   "meaning": "Feet that slip.", "params": {"effect.friction_forward": {"index": 0,
   "value": 0.8, "lo": 0, "hi": 3}}, "train": 0.001, "held_out": 0.0012, "delta_bic": -812},
 )");
  auto w = ReportWords(report);
  ASSERT_TRUE(w.ok()) << w.status();
  const size_t structure = w->find("the model's structure: friction.anisotropic, fitted into "
                                   "the baseline (delta BIC -812.0)");
  ASSERT_NE(structure, std::string::npos) << *w;
  EXPECT_LT(structure, w->find("found tether.constant")) << *w;
  EXPECT_LT(structure, w->find("effect.friction_forward")) << *w;
  auto without = ReportWords(std::string(kFound).insert(1, R"("structure": null, )"));
  ASSERT_TRUE(without.ok()) << without.status();
  EXPECT_EQ(without->find("structure"), std::string::npos) << *without;
}

// A named explanation that only corrects the model's idealisations (every part in the
// report's `structural`) is said to be structure, not left-out physics; a tether is not.
TEST(ReportWords, AFoundStructureIsSaidToBeTheModelsIdealisationNotMissingPhysics) {
  std::string report = kFound;
  report.replace(report.find("\"tether.constant\""), 17,
                 R"("friction.anisotropic", "structural": ["friction.anisotropic"])");
  auto w = ReportWords(report);
  ASSERT_TRUE(w.ok()) << w.status();
  EXPECT_NE(w->find("friction.anisotropic corrects the model's own idealisations (its "
                    "structure), not physics it left out"),
            std::string::npos)
      << *w;
  // A pair with a part that is not structural, and a report without the list, say nothing.
  std::string pair = kFound;
  pair.replace(pair.find("\"tether.constant\""), 17,
               R"("friction.anisotropic+tether.constant", "structural": ["friction.anisotropic"])");
  for (const std::string& r : {pair, std::string(kFound)}) {
    auto v = ReportWords(r);
    ASSERT_TRUE(v.ok()) << v.status();
    EXPECT_EQ(v->find("idealisations"), std::string::npos) << *v;
  }
}

// Numerics first: the step the diagnosis moved to is said before the verdict, with the
// uncalibrated model's errors at both steps.
TEST(ReportWords, AMoveToAFinerStepIsSaidBeforeTheVerdict) {
  std::string report = kFound;
  report.insert(report.find("\"effects\""),
                R"("numerics": {"from_ms": 1, "at_ms": 0.5, "from_training_error": 0.0044,
   "at_training_error": 0.0024}, )");
  auto w = ReportWords(report);
  ASSERT_TRUE(w.ok()) << w.status();
  const size_t said = w->find("the model's numerics: its 1 ms step missed the training "
                              "recordings by 4.4 mm, 0.5 ms by 2.4 mm, so the diagnosis ran at "
                              "0.5 ms");
  ASSERT_NE(said, std::string::npos) << *w;
  EXPECT_LT(said, w->find("found tether.constant")) << *w;
}

TEST(ReportWords, NotJsonIsAnErrorSayingSo) {
  auto w = ReportWords("{verdict");
  ASSERT_FALSE(w.ok());
  EXPECT_NE(w.status().message().find("not JSON"), std::string::npos);
}

}  // namespace
}  // namespace gaitforge::diagnosis
