#pragma once
// Paper 004's acceleration fitness (../shared/papers/004_*, "Estimation"): how far a
// model's accelerations are from the recorded ones, relative to the recorded ones,
//   F = 1 - |a_sim - a_rec| / |a_rec|,
// pooled over a window of samples and the compared points, as pure functions on sampled
// signals (no ODE). Accelerations come from positions by a Savitzky-Golay second derivative
// (a least-squares cubic over 2m + 1 samples: m = 4, 9 samples, as the arm's fact sheet
// chooses for motion capture at 100 Hz), applied alike to the recorded and the simulated
// positions so that the filter's smoothing is the same on both sides.
#include <span>
#include <vector>

#include "workers/objectives/calibration_error.h"

namespace gaitforge::calibration {

inline constexpr int kSavitzkyGolayHalfWindow = 4;

// The second derivative of x (samples dt apart) by a Savitzky-Golay filter of order 2 or 3
// (the same weights) over 2 half_window + 1 samples, at every sample whose whole window lies
// in x; NaN at the first and last half_window samples.
std::vector<double> SavitzkyGolaySecondDerivative(std::span<const double> x, double dt,
                                                  int half_window = kSavitzkyGolayHalfWindow);

// A point's acceleration over time: one signal per axis (1 to 3), signals[axis][i].
using Vectors = Signals;

// The relative error of simulated against recorded accelerations over samples
// [begin, end) of every point: MAE: sum_i sum_p |a_sim - a_rec| / sum_i sum_p |a_rec|; RMSE:
// the square root of the same ratio of squared norms (|.| the Euclidean norm over a
// point's axes). Samples where either side is NaN are left out. A negative value when the
// recorded accelerations are all zero there (nothing to compare with).
double RelativeAccelerationError(Metric metric, const std::vector<Vectors>& real,
                                 const std::vector<Vectors>& sim, int64_t begin, int64_t end);

}  // namespace gaitforge::calibration
