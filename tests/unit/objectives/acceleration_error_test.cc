// Paper 004's acceleration fitness pieces (workers/objectives/acceleration_error.h): the
// Savitzky-Golay second derivative is exact on cubics and has the known 9-point weights,
// and the relative error pools points by their vector norms.
#include "workers/objectives/acceleration_error.h"

#include <cmath>
#include <vector>

#include "gtest/gtest.h"

namespace gaitforge::calibration {
namespace {

TEST(SavitzkyGolayTest, ExactOnACubic) {
  const double dt = 0.01;
  std::vector<double> x;
  for (int k = 0; k < 40; ++k) {
    const double t = k * dt;
    x.push_back(0.3 - 2 * t + 1.5 * t * t - 4 * t * t * t);
  }
  const auto a = SavitzkyGolaySecondDerivative(x, dt);
  ASSERT_EQ(a.size(), x.size());
  for (int k = 0; k < 4; ++k) EXPECT_TRUE(std::isnan(a[k]) && std::isnan(a[39 - k]));
  for (int k = 4; k < 36; ++k) EXPECT_NEAR(a[k], 3 - 24 * k * dt, 1e-9) << k;
}

TEST(SavitzkyGolayTest, NineSampleWeights) {
  // The tabulated weights (28, 7, -8, -17, -20, -17, -8, 7, 28) / 462: a unit impulse at
  // sample 4 + j shows weight j at sample 4.
  const double w[] = {28, 7, -8, -17, -20, -17, -8, 7, 28};
  for (int j = -4; j <= 4; ++j) {
    std::vector<double> x(9, 0.0);
    x[4 + j] = 1;
    EXPECT_NEAR(SavitzkyGolaySecondDerivative(x, 1.0)[4], w[j + 4] / 462, 1e-15) << j;
  }
}

TEST(SavitzkyGolayTest, SmoothsJitter) {
  // Jitter of +-0.1 mm from sample to sample at 100 Hz: the plain second difference makes
  // 4 m/s^2 of it; the nine-sample fit, sum (-1)^j w_j = 40 of 462, about 2% of that.
  std::vector<double> x;
  for (int k = 0; k < 20; ++k) x.push_back(k % 2 ? 1e-4 : -1e-4);
  const auto a = SavitzkyGolaySecondDerivative(x, 0.01);
  EXPECT_NEAR(a[10], -40.0 / 462, 1e-12);
  EXPECT_LT(std::fabs(a[10]), 0.05 * 4);
}

TEST(RelativeAccelerationErrorTest, NormsOverAPointsAxes) {
  // One point, two axes, two samples: recorded (3, 4) and (0, 0); simulated (0, 0), (0, 1).
  const std::vector<Vectors> real = {{{3, 0}, {4, 0}}};
  const std::vector<Vectors> sim = {{{0, 0}, {0, 1}}};
  EXPECT_NEAR(RelativeAccelerationError(Metric::kMae, real, sim, 0, 2), (5.0 + 1.0) / 5.0, 1e-12);
  EXPECT_NEAR(RelativeAccelerationError(Metric::kRmse, real, sim, 0, 2), std::sqrt(26.0 / 25.0),
              1e-12);
  EXPECT_DOUBLE_EQ(RelativeAccelerationError(Metric::kMae, real, real, 0, 2), 0.0);
}

TEST(RelativeAccelerationErrorTest, SkipsUnfilteredSamplesAndRefusesZeroMotion) {
  const double nan = std::nan("");
  const std::vector<Vectors> real = {{{nan, 2, 0}}};
  const std::vector<Vectors> sim = {{{5, 1, 0}}};
  EXPECT_NEAR(RelativeAccelerationError(Metric::kMae, real, sim, 0, 3), 0.5, 1e-12);
  EXPECT_LT(RelativeAccelerationError(Metric::kMae, real, sim, 2, 3), 0);
}

}  // namespace
}  // namespace gaitforge::calibration
