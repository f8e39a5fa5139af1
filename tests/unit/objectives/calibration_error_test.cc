// The calibration error measures (workers/objectives/calibration_error.h) with hand-computed
// values: MAE, RMSE, median and profiled offsets, the shift-invariant errors, interpolation,
// whole cycles, period averaging, slopes and distance per cycle.
#include <cmath>
#include <cstdint>
#include <numbers>
#include <utility>
#include <vector>

#include "gmock/gmock.h"
#include "gtest/gtest.h"
#include "workers/objectives/calibration_error.h"

namespace gaitforge::calibration {
namespace {

namespace cal = calibration;

TEST(CalibrationError, MaeRmseMedianAndOffsets) {
  const std::vector<double> a = {1, 2, 3}, b = {1, 1, 1};
  EXPECT_DOUBLE_EQ(cal::Mae(a, b), 1.0);                  // (0 + 1 + 2) / 3
  EXPECT_DOUBLE_EQ(cal::Rmse(a, b), std::sqrt(5.0 / 3));  // (0 + 1 + 4) / 3
  EXPECT_DOUBLE_EQ(cal::Median({3, 1, 2}), 2.0);
  EXPECT_DOUBLE_EQ(cal::Median({4, 1, 3, 2}), 2.5);
  const std::vector<double> real = {1, 2, 6}, zero = {0, 0, 0};
  EXPECT_DOUBLE_EQ(cal::ProfiledOffset(cal::Metric::kRmse, real, zero), 3.0);  // mean
  EXPECT_DOUBLE_EQ(cal::ProfiledOffset(cal::Metric::kMae, real, zero), 2.0);   // median
  // Pooled over channels: channel 0 is off by a constant (profiled away), channel 1 has
  // residuals {1, -1} after its mean 0.
  std::vector<double> offsets;
  const double e = cal::PooledError(cal::Metric::kRmse, {{1, 2}, {1, -1}}, {{0, 1}, {0, 0}}, 0, 2,
                                    0, true, &offsets);
  EXPECT_DOUBLE_EQ(e, std::sqrt(2.0 / 4));  // (0 + 0 + 1 + 1) / 4
  EXPECT_THAT(offsets, ::testing::ElementsAre(1.0, 0.0));
  // Without profiling: residuals 1, 1, 1, -1.
  EXPECT_DOUBLE_EQ(
      cal::PooledError(cal::Metric::kMae, {{1, 2}, {1, -1}}, {{0, 1}, {0, 0}}, 0, 2, 0, false),
      1.0);
}

TEST(CalibrationError, ShiftInvariantFindsTheShiftAndOffset) {
  // real[2] = 1 pairs with sim[3] = 1: shift +1; sim also 5 higher (offset -5).
  const cal::Signals real = {{0, 0, 1, 0, 0, 0}};
  const cal::Signals sim = {{5, 5, 5, 6, 5, 5}};
  const auto r = cal::ShiftInvariantError(cal::Metric::kMae, real, sim, 2, true);
  EXPECT_EQ(r.shift, 1);
  EXPECT_DOUBLE_EQ(r.error, 0.0);
  ASSERT_EQ(r.offsets.size(), 1u);
  EXPECT_DOUBLE_EQ(r.offsets[0], -5.0);
  // Without profiling the constant 5 stays: MAE 5 at every shift; ties go to shift 0.
  const auto r0 = cal::ShiftInvariantError(cal::Metric::kMae, real, {{0, 0, 0, 0, 0, 0}}, 2, false);
  EXPECT_EQ(r0.shift, 0);
  EXPECT_DOUBLE_EQ(r0.error, 1.0 / 6);
  // The peak 2 samples later: found with max_shift 2 (the overlap at s = 2 is
  // real[0..4] = sim[2..6]), not with max_shift 1.
  const cal::Signals early = {{0, 1, 0, 0, 0, 0, 0}}, late = {{0, 0, 0, 1, 0, 0, 0}};
  const auto r2 = cal::ShiftInvariantError(cal::Metric::kRmse, early, late, 2, false);
  EXPECT_EQ(r2.shift, 2);
  EXPECT_DOUBLE_EQ(r2.error, 0.0);
  const auto r1 = cal::ShiftInvariantError(cal::Metric::kRmse, early, late, 1, false);
  EXPECT_GT(r1.error, 0.0);
  // The other way round: shift -2.
  EXPECT_EQ(cal::ShiftInvariantError(cal::Metric::kRmse, late, early, 2, false).shift, -2);
}

TEST(CalibrationError, PaddedShiftComparesEverySample) {
  // real[i] pairs with sim[i + 1 + s]; {1, 2, 3} sits at sim[0..2]: s = -1.
  const auto r =
      cal::PaddedShiftInvariantError(cal::Metric::kRmse, {{1, 2, 3}}, {{1, 2, 3, 9, 9}}, 1, false);
  EXPECT_EQ(r.shift, -1);
  EXPECT_DOUBLE_EQ(r.error, 0.0);
  // With offsets: {2, 3, 4} at s = 0 is real - 1 ... plus 1: offset -1.
  const auto p =
      cal::PaddedShiftInvariantError(cal::Metric::kRmse, {{1, 2, 3}}, {{9, 2, 3, 4, 9}}, 1, true);
  EXPECT_EQ(p.shift, 0);
  EXPECT_DOUBLE_EQ(p.error, 0.0);
  EXPECT_THAT(p.offsets, ::testing::ElementsAre(-1.0));
  // Hand-computed, offsets profiled, sim {9, 2, 3, 9, 9}:
  //   s = -1: {9, 2, 3}: residuals -8, 0, 0, mean -8/3 -> -16/3, 8/3, 8/3: RMSE sqrt(384/27)
  //   s =  0: {2, 3, 9}: residuals -1, -1, -6, mean -8/3 -> 5/3, 5/3, -10/3: sqrt(150/27)
  //   s = +1: {3, 9, 9}: residuals -2, -7, -6, mean -5 -> 3, -2, -1: sqrt(14/3), the best.
  const auto q =
      cal::PaddedShiftInvariantError(cal::Metric::kRmse, {{1, 2, 3}}, {{9, 2, 3, 9, 9}}, 1, true);
  EXPECT_EQ(q.shift, 1);
  EXPECT_NEAR(q.error, std::sqrt(14.0 / 3), 1e-12);
  EXPECT_THAT(q.offsets, ::testing::ElementsAre(-5.0));
  EXPECT_NEAR(cal::PooledError(cal::Metric::kRmse, {{1, 2, 3}}, {{9, 2, 3, 9, 9}}, 0, 3, 1, true),
              std::sqrt(150.0 / 27), 1e-12);
}

std::pair<int64_t, int64_t> Cycles(int64_t begin, int64_t end) { return {begin, end}; }

TEST(CalibrationError, InterpolationAndCycles) {
  const std::vector<double> t = {0, 1, 2}, x = {0, 10, 0};
  EXPECT_DOUBLE_EQ(cal::Interpolate(t, x, 0.5), 5.0);
  EXPECT_DOUBLE_EQ(cal::Interpolate(t, x, 1.0), 10.0);
  EXPECT_DOUBLE_EQ(cal::Interpolate(t, x, 1.25), 7.5);
  EXPECT_DOUBLE_EQ(cal::Interpolate(t, x, -1), 0.0);
  EXPECT_DOUBLE_EQ(cal::Interpolate(t, x, 3), 0.0);
  EXPECT_EQ(cal::BinsPerPeriod(0.8, 0.01), 80);
  EXPECT_EQ(cal::BinsPerPeriod(0.805, 0.01), 81);  // round(80.5)
  EXPECT_EQ(cal::BinsPerPeriod(0.01, 0.01), 2);
  // Period 1 in 10 bins: cycle k's last bin is at k + 0.9.
  EXPECT_EQ(cal::WholeCycles(0, 1.95, 1.0, 10, 0), Cycles(0, 2));
  EXPECT_EQ(cal::WholeCycles(0, 1.9, 1.0, 10, 0), Cycles(0, 2));
  EXPECT_EQ(cal::WholeCycles(0, 1.85, 1.0, 10, 0), Cycles(0, 1));
  EXPECT_EQ(cal::WholeCycles(0.05, 2.95, 1.0, 10, 0), Cycles(1, 3));
  EXPECT_EQ(cal::WholeCycles(0.05, 2.95, 1.0, 10, 0.05), Cycles(0, 3));
  const auto none = cal::WholeCycles(0.5, 1.2, 1.0, 10, 0);
  EXPECT_EQ(none.first, none.second);
}

TEST(CalibrationError, PeriodAveragingKeepsShapeAndDrift) {
  // x = i mod 4 + 10 * cycle, dt = 1, T = 4, 13 samples: 3 whole cycles (the 13th sample
  // starts a 4th): average i + 10 * (0 + 1 + 2) / 3.
  std::vector<double> x;
  for (int i = 0; i < 13; ++i) x.push_back(i % 4 + 10 * (i / 4));
  EXPECT_THAT(cal::PeriodAverageSampled(x, 1.0, 4.0), ::testing::ElementsAre(10, 11, 12, 13));
  // Padding: the ramp x = t over cycle 1 with one bin either side: times 3 .. 8.
  std::vector<double> t(12), ramp(12);
  for (int i = 0; i < 12; ++i) t[i] = ramp[i] = i;
  EXPECT_THAT(cal::PeriodAverage(t, ramp, 4.0, 4, 0.0, 1, 2, 1),
              ::testing::ElementsAre(3, 4, 5, 6, 7, 8));
  // Origin 0.5: times 0.5 + 4k + i, averaged over k = 0, 1: 2.5 + i.
  EXPECT_THAT(cal::PeriodAverage(t, ramp, 4.0, 4, 0.5, 0, 2),
              ::testing::ElementsAre(2.5, 3.5, 4.5, 5.5));
  EXPECT_TRUE(cal::PeriodAverage(t, ramp, 4.0, 4, 0.0, 2, 2).empty());
}

TEST(CalibrationError, SlopeAndDistancePerCycle) {
  const std::vector<double> t4 = {0, 1, 2, 3};
  EXPECT_DOUBLE_EQ(cal::LeastSquaresSlope(t4, std::vector<double>{1, 3, 5, 7}), 2.0);
  // mean t 1.5, mean x 1; sum dt dx = 1.5 + 0 + 0 + 1.5 = 3; sum dt^2 = 5.
  EXPECT_DOUBLE_EQ(cal::LeastSquaresSlope(t4, std::vector<double>{0, 1, 1, 2}), 0.6);
  EXPECT_THAT(cal::MeanSignal({{1, 2}, {3, 6}}), ::testing::ElementsAre(2, 4));
  // 1 cm per cycle of 0.5 s plus a 3 mm oscillation at the gait period, over 20 cycles.
  std::vector<double> t, x;
  for (int i = 0; i < 1000; ++i) {
    t.push_back(i * 0.01);
    x.push_back(0.02 * t.back() + 0.003 * std::cos(2 * std::numbers::pi * t.back() / 0.5));
  }
  EXPECT_NEAR(cal::DistancePerCycle(t, x, 0.5), 0.01, 1e-5);
}

}  // namespace
}  // namespace gaitforge::calibration
