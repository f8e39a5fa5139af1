// What a calibration's recordings leave open (services/coordinator/open_ranges.h), and a gait
// study from a calibration stored in a real SQLite file taking those ranges.
#include "services/coordinator/open_ranges.h"

#include <gtest/gtest.h>

#include "services/coordinator/from_calibration.h"
#include "tests/unit/coordinator/calibration_fixture.h"

namespace gaitforge::coordinator {
namespace {

storage::IndividualRecord Evaluation(int generation, int member, std::vector<double> genes,
                                     std::vector<double> errors, bool valid = true) {
  storage::IndividualRecord r;
  r.study_id = "cal-1";
  r.generation = generation;
  r.member = member;
  r.genes = std::move(genes);
  r.valid = valid;
  double mean = 0;
  for (size_t i = 0; i < errors.size(); ++i) {
    r.metrics["error_" + std::to_string(i)] = errors[i];
    mean += errors[i] / errors.size();
  }
  r.metrics["error"] = mean;
  r.fitness = -mean;
  return r;
}

TEST(StudentT95, TableAndItsTail) {
  EXPECT_DOUBLE_EQ(StudentT95(1), 6.314);
  EXPECT_DOUBLE_EQ(StudentT95(4), 2.132);
  EXPECT_DOUBLE_EQ(StudentT95(30), 1.697);
  EXPECT_NEAR(StudentT95(60), 1.671, 0.003);
  EXPECT_NEAR(StudentT95(100000), 1.645, 0.001);
  EXPECT_TRUE(std::isnan(StudentT95(0)));
}

TEST(OpenRanges, RecordingErrorsAreTheNumberedOnesInOrder) {
  auto r = Evaluation(0, 0, {1}, {0.3, 0.1, 0.2});
  EXPECT_EQ(RecordingErrors(r), (std::vector<double>{0.3, 0.1, 0.2}));
  r.metrics.erase("error_1");
  EXPECT_EQ(RecordingErrors(r), (std::vector<double>{0.3}));  // a gap ends the list
}

// Worse on every recording by about the same is told apart; worse on one and better on
// others, with the same mean cost, is not: the recordings disagree about it.
TEST(OpenRanges, IndistinguishableWhenThePairedDifferencesDoNotSaySo) {
  const std::vector<double> best = {1.0, 1.0, 1.0, 1.0, 1.0};
  EXPECT_TRUE(IndistinguishableFrom(best, best));
  EXPECT_FALSE(IndistinguishableFrom(best, {1.1, 1.1, 1.12, 1.09, 1.1}));
  EXPECT_TRUE(IndistinguishableFrom(best, {1.5, 0.9, 0.95, 0.8, 0.9}));
  EXPECT_TRUE(IndistinguishableFrom(best, {0.9, 0.9, 0.9, 0.9, 0.9}));  // better
  EXPECT_FALSE(IndistinguishableFrom(best, {1.0, 1.0, 1.0, 1.0}));   // another count
  EXPECT_FALSE(IndistinguishableFrom({1.0}, {1.0}));                  // one recording
  EXPECT_FALSE(IndistinguishableFrom(best, {0, 1, 1, 1, 1}));         // an error of 0
}

// One recording the model misses by far more than the others must not decide alone: the
// uncalibrated model of MuJoCo's calibration (5.6, 2.3, 0.9, 0.9, 1.7 mm against the fit's
// 0.6, 0.6, 0.6, 0.6, 1.2) passed a test on differences; on ratios it does not.
TEST(OpenRanges, ARecordingWithALargeErrorDoesNotDecideAlone) {
  EXPECT_FALSE(IndistinguishableFrom({0.6, 0.6, 0.6, 0.6, 1.2}, {5.6, 2.3, 0.9, 0.9, 1.7}));
}

TEST(OpenRanges, TheExtentOfWhatFitsAsWellSkippingInvalidAndOtherSizes) {
  const auto best = Evaluation(3, 0, {5.0, 0.5}, {1.0, 1.0, 1.0});
  const std::vector<storage::IndividualRecord> all = {
      best,
      Evaluation(1, 2, {3.0, 0.7}, {1.3, 0.8, 0.95}),   // as good: widens both
      Evaluation(1, 3, {9.0, 0.1}, {2.0, 2.1, 1.9}),    // worse everywhere
      Evaluation(2, 0, {1.0, 0.9}, {1.0, 1.0, 1.0}, false),  // invalid
      Evaluation(2, 1, {7.0}, {1.0, 1.0, 1.0}),         // another gene count
  };
  const auto fits = FitsLeftOpen(all, best, 2);
  EXPECT_EQ(fits.size(), 2u);  // best itself and the one as good
  auto r = Extent(fits);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_DOUBLE_EQ(r[0].lo, 3.0);
  EXPECT_DOUBLE_EQ(r[0].hi, 5.0);
  EXPECT_DOUBLE_EQ(r[1].lo, 0.5);
  EXPECT_DOUBLE_EQ(r[1].hi, 0.7);
  EXPECT_TRUE(Extent(FitsLeftOpen(all, Evaluation(0, 0, {5, 0.5}, {1.0}), 2)).empty());
}

TEST(OpenRanges, TheFitsAreBestFirstThenTheOthersAsGood) {
  const auto best = Evaluation(3, 0, {5.0, 0.5}, {1.0, 1.0, 1.0});
  const std::vector<storage::IndividualRecord> all = {
      Evaluation(1, 2, {3.0, 0.7}, {1.3, 0.8, 0.95}), best,
      Evaluation(1, 3, {9.0, 0.1}, {2.0, 2.1, 1.9}), Evaluation(2, 4, {4.0, 0.6}, {1.0, 1.1, 0.9})};
  const auto fits = FitsLeftOpen(all, best, 2);
  ASSERT_EQ(fits.size(), 3u);  // best once, though it is among the evaluations too
  EXPECT_EQ(fits[0], best.genes);
  EXPECT_EQ(fits[1], (std::vector<double>{3.0, 0.7}));
  EXPECT_EQ(fits[2], (std::vector<double>{4.0, 0.6}));
}

// Farthest-point order: a crowd where the search converged yields one point, and the
// corners of the set come before the crowd's other members.
TEST(OpenRanges, ACoverSpreadsOverTheSetNotItsCrowd) {
  std::vector<std::vector<double>> points = {{0.50, 1e-4}};
  for (int i = 0; i < 20; ++i) points.push_back({0.50 + 0.001 * i, 1.1e-4});  // the crowd
  points.push_back({0.0, 1e-3});
  points.push_back({1.0, 1e-6});
  const std::vector<GeneRange> scale = {{0, 1}, {1e-6, 1e-2}};
  const auto order = Cover(points, scale, {false, true}, 3);
  ASSERT_EQ(order.size(), 3u);
  EXPECT_EQ(order[0], 0u);
  EXPECT_EQ(std::vector<size_t>(order.begin() + 1, order.end()), (std::vector<size_t>{22, 21}));
  EXPECT_EQ(Cover(points, scale, {false, true}, 100).size(), points.size());
  EXPECT_TRUE(Cover({}, scale, {}, 4).empty());
}

TEST(OpenRanges, HullTakesWhatEitherHas) {
  auto h = Hull({{1, 2}, {}, {0, 1}}, {{1.5, 3}, {4, 5}});
  ASSERT_EQ(h.size(), 3u);
  EXPECT_DOUBLE_EQ(h[0].lo, 1);
  EXPECT_DOUBLE_EQ(h[0].hi, 3);
  EXPECT_DOUBLE_EQ(h[1].lo, 4);
  EXPECT_DOUBLE_EQ(h[2].hi, 1);
}

// The whole path through a real database: a completed calibration with two generations of
// evaluations; the gait study's ensemble spans the evaluations as good as the best, far
// wider than the search's final spread.
TEST(FromCalibration, TheEnsembleSpansWhatTheRecordingsLeaveOpen) {
  testing::TempDir dir;
  auto store = StoreWithCalibration(dir, "cal-1", "running");
  ASSERT_NE(store, nullptr);
  const std::vector<std::vector<storage::IndividualRecord>> generations = {
      {Evaluation(0, 0, {8.0, 0.8, 0.0}, {1.2, 0.7, 0.9}), Evaluation(0, 1, {10.5, 1.3, 0.04}, {3, 3, 3})},
      {Evaluation(1, 0, {9.5, 1.0, 0.01}, {0.8, 0.8, 0.8}), Evaluation(1, 1, {9.6, 1.05, -0.03}, {0.9, 0.8, 0.9})}};
  for (int g = 0; g < 2; ++g) {
    ASSERT_TRUE(store->AppendResults(generations[g]).get().ok());
    storage::GenerationRecord gen;
    gen.study_id = "cal-1";
    gen.generation = g;
    gen.evaluations = 2;
    storage::HofRecord hof;
    hof.origin_generation = g == 0 ? 0 : 1;
    hof.origin_member = 0;
    hof.genes = g == 0 ? std::vector<double>{8.0, 0.8, 0.0} : std::vector<double>{9.5, 1.0, 0.01};
    hof.valid = true;
    hof.fitness = -0.8;
    gen.hall_of_fame = {hof};
    gen.study_state = g == 1 ? "completed" : "running";
    ASSERT_TRUE(store->CommitGeneration(gen).get().ok());
  }
  ASSERT_TRUE(store->SetStudyState("cal-1", "completed", "").get().ok());
  const SpreadFn spread = [](const std::string&, int) { return std::vector<double>{0.01, 0.01, 0.001}; };
  v1::StudySpec g;
  g.mutable_objective()->set_from_calibration("cal-1");
  g.mutable_objective()->mutable_robust();
  ASSERT_TRUE(ResolveFromCalibration(*store, spread, &g).ok());
  const auto& p = g.objective().robust().parameters();
  ASSERT_EQ(p.size(), 2);
  EXPECT_EQ(g.objective().options().at("set"), "actuators.force_n=9.5,scale.link_stiffness=1");
  // 8.0 / 0.8 fit as well as the best (better on one recording, worse on another): kept;
  // 10.5 / 1.3 is worse on all three: not.
  EXPECT_DOUBLE_EQ(p[0].lo(), 8.0);
  EXPECT_DOUBLE_EQ(p[0].hi(), 9.6);
  EXPECT_DOUBLE_EQ(p[1].lo(), 0.8);
  EXPECT_DOUBLE_EQ(p[1].hi(), 1.05);
}

}  // namespace
}  // namespace gaitforge::coordinator
