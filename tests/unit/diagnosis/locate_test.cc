// Reading the located slices against the model's own spread (services/diagnosis/locate.h):
// what a "none" verdict then says, on located JSONs shaped as gaitforge_locate.py writes them.
#include "services/diagnosis/locate.h"

#include <gtest/gtest.h>

#include <string>

namespace gaitforge::diagnosis {
namespace {

std::string Located(const std::string& beyond, const std::string& names) {
  return R"({"noise_m": 0.0004, "variants": 6, "beyond_spread": )" + beyond +
         R"(, "beyond_recordings": )" + names + R"(, "summary": "..."})";
}

const std::vector<std::string> kHeld = {"/x/runs/recordings/2611c428598c6588-gait-c.csv"};

TEST(OwnName, DropsTheHashPrefixOfADownloadedCopyOnly) {
  EXPECT_EQ(OwnName("/d/2611c428598c6588-gait-c.csv"), "gait-c.csv");
  EXPECT_EQ(OwnName("/d/gait-c.csv"), "gait-c.csv");
  EXPECT_EQ(OwnName("/d/walking-forward-take-3.csv"), "walking-forward-take-3.csv");  // not hex
}

TEST(ReadSpread, KnownOnlyWhenLocatedAgainstTheVariants) {
  SpreadReading r = ReadSpread(Located("true", R"(["c35797bb581b521b-gait-b.csv"])"),
                               Located("false", "[]"));
  EXPECT_TRUE(r.train_known);
  EXPECT_TRUE(r.train_beyond);
  EXPECT_TRUE(r.held_known);
  EXPECT_FALSE(r.held_beyond);
  ASSERT_EQ(r.train_showing.size(), 1u);
  EXPECT_EQ(r.train_showing[0], "gait-b.csv");
  // Against the noise alone (no --variants): null, not known; a failed locate: "{}".
  r = ReadSpread(Located("null", "null"), "{}");
  EXPECT_FALSE(r.train_known);
  EXPECT_FALSE(r.held_known);
  r = ReadSpread("not json", "");
  EXPECT_FALSE(r.train_known);
}

TEST(ReadNone, TrainingBeyondHeldOutWithinCannotBeConfirmed) {
  const NoneReading n = ReadNone(
      ReadSpread(Located("true", R"(["c35797bb581b521b-gait-b.csv"])"), Located("false", "[]")),
      kHeld, "tether.constant");
  EXPECT_TRUE(n.unexplained);
  EXPECT_NE(n.words.find("still misses the training recordings beyond"), std::string::npos);
  EXPECT_NE(n.words.find("closest held out: tether.constant"), std::string::npos);
  EXPECT_NE(n.experiment.find("held-out recordings (gait-c.csv)"), std::string::npos)
      << n.experiment;
  EXPECT_NE(n.experiment.find("as gait-b.csv does"), std::string::npos) << n.experiment;
}

TEST(ReadNone, NamesEveryTrainingRecordingThatShowsIt) {
  const NoneReading n =
      ReadNone(ReadSpread(Located("true", R"(["gait-a.csv", "gait-b.csv"])"),
                          Located("false", "[]")),
               kHeld, "");
  EXPECT_NE(n.experiment.find("as gait-a.csv, gait-b.csv do)"), std::string::npos)
      << n.experiment;
}

TEST(ReadNone, BothBeyondIsUnexplainedWithNoRecordingToAdd) {
  const NoneReading n = ReadNone(
      ReadSpread(Located("true", R"(["gait-a.csv"])"), Located("true", R"(["gait-c.csv"])")),
      kHeld, "");
  EXPECT_TRUE(n.unexplained);
  EXPECT_NE(n.words.find("training and held-out recordings beyond"), std::string::npos);
  EXPECT_EQ(n.words.find("closest"), std::string::npos);
  EXPECT_TRUE(n.experiment.empty());
}

TEST(ReadNone, HeldOutBeyondTrainingWithinMeansTheTrainingGaitsDoNotExciteIt) {
  const NoneReading n = ReadNone(
      ReadSpread(Located("false", "[]"), Located("true", R"(["2611c428598c6588-gait-c.csv"])")),
      kHeld, "mass.offset");
  EXPECT_TRUE(n.unexplained);
  EXPECT_NE(n.words.find("misses the held-out recordings beyond it"), std::string::npos);
  EXPECT_NE(n.experiment.find("held-out ones (gait-c.csv)"), std::string::npos) << n.experiment;
  EXPECT_NE(n.experiment.find("train on a gait like the held-out one"), std::string::npos);
}

TEST(ReadNone, WithinEverywhereIsAMatchAndUnknownSaysNothing) {
  NoneReading n = ReadNone(ReadSpread(Located("false", "[]"), Located("false", "[]")), kHeld, "");
  EXPECT_FALSE(n.unexplained);
  EXPECT_EQ(n.words, "the calibrated model matches the training and held-out recordings within "
                     "the noise and its own numeric spread");
  EXPECT_TRUE(n.experiment.empty());
  n = ReadNone(ReadSpread("{}", Located("true", "[]")), kHeld, "x");
  EXPECT_FALSE(n.unexplained);
  EXPECT_TRUE(n.words.empty());
  EXPECT_TRUE(n.experiment.empty());
}

}  // namespace
}  // namespace gaitforge::diagnosis
