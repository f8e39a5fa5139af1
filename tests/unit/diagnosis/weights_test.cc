// The training recordings' weights from their numeric floors (WeightsFromFloors, fits.h):
// floor weights follow 1 / sd^2; pooled weights add the median floor, so that no recording
// carries a fit alone while a chaotic one still counts less.
#include <gtest/gtest.h>

#include <numeric>
#include <vector>

#include "services/diagnosis/fits.h"

namespace gaitforge::diagnosis {
namespace {

double Sum(const std::vector<double>& w) { return std::accumulate(w.begin(), w.end(), 0.0); }

// Floors of two training gaits as a MuJoCo build's recordings gave them (mm): the first
// gait's error moves by 1.15 mm with the model's numerics, the second's by 0.30 mm.
const std::vector<double> kTwoGaits = {1.15, 0.30};

TEST(WeightsFromFloors, FloorWeightsFollowTheInverseSquareOfEachFloor) {
  const auto w = WeightsFromFloors(kTwoGaits, false);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NEAR(Sum(w), 2.0, 1e-12);
  EXPECT_NEAR(w[1] / w[0], (1.15 * 1.15) / (0.30 * 0.30), 1e-9);
}

TEST(WeightsFromFloors, PooledWeightsAddTheMedianFloorToEach) {
  const auto w = WeightsFromFloors(kTwoGaits, true);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_NEAR(Sum(w), 2.0, 1e-12);
  const double m = 0.5 * (1.15 + 0.30);  // the median of two: their mean
  EXPECT_NEAR(w[1] / w[0], (1.15 * 1.15 + m * m) / (0.30 * 0.30 + m * m), 1e-9);
  EXPECT_GT(w[1], w[0]);       // the regular gait still counts more
  EXPECT_LT(w[1] / w[0], 4.0);  // but not 15 times as much
}

TEST(WeightsFromFloors, PooledWeightsKeepOneSteadyRecordingFromCarryingTheFit) {
  // One recording the model's numerics barely move among four ordinary ones.
  const std::vector<double> floors = {0.01, 1.0, 1.2, 0.9, 1.1};
  const auto floor = WeightsFromFloors(floors, false);
  const auto pooled = WeightsFromFloors(floors, true);
  EXPECT_GT(floor[0], 0.8 * Sum(floor));  // floor weights: it carries the fit
  EXPECT_LT(pooled[0], 0.4 * Sum(pooled));
  for (size_t i = 1; i < floors.size(); ++i) EXPECT_LT(pooled[0], 3.0 * pooled[i]);
}

TEST(WeightsFromFloors, AChaoticRecordingStillCountsLessWhenPooled) {
  const std::vector<double> floors = {5.0, 1.0, 1.0};
  const auto pooled = WeightsFromFloors(floors, true);
  EXPECT_LT(pooled[0], 0.1 * pooled[1]);
  EXPECT_NEAR(Sum(pooled), 3.0, 1e-12);
}

TEST(WeightsFromFloors, NoFloorsNoWeights) {
  EXPECT_TRUE(WeightsFromFloors({}, true).empty());
  EXPECT_TRUE(WeightsFromFloors({}, false).empty());
}

}  // namespace
}  // namespace gaitforge::diagnosis
