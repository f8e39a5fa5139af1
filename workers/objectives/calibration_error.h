#pragma once
// Error measures between a recording and a simulation, as pure functions on sampled signals
// (no ODE): the pieces of every calibration objective (a dedicated model's and
// "robot.calibration"), after the calibration method of paper 003 (../shared/papers/003_*):
// a phase-shift-invariant mean absolute error (its eq. 4) between signals averaged over the
// gait period.
//
// Conventions: a "signal" is one channel's samples; "signals" are several channels of equal
// length, channel-major (signals[c][i]). Residuals are real - sim; an offset is the constant
// added to the simulation to match the recording (real ~ sim + offset). Errors over several
// channels are pooled: the RMSE is sqrt of the mean squared residual over all channels and
// samples, the MAE the mean absolute residual over all of them.
#include <cstdint>
#include <functional>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"

namespace gaitforge::calibration {

using Signals = std::vector<std::vector<double>>;

enum class Metric { kRmse, kMae };
// "rmse" | "mae".
absl::StatusOr<Metric> ParseMetric(std::string_view name);

// Mean absolute and root-mean-square difference of two equally long signals (0 when empty).
double Mae(std::span<const double> a, std::span<const double> b);
double Rmse(std::span<const double> a, std::span<const double> b);
double Error(Metric metric, std::span<const double> a, std::span<const double> b);

// The median (mean of the two middle values for an even count); 0 when empty.
double Median(std::vector<double> values);

// The constant offset c minimising Error(metric, real, sim + c): the mean residual for the
// RMSE, the median residual for the MAE.
double ProfiledOffset(Metric metric, std::span<const double> real, std::span<const double> sim);

// Pooled error between real[c][i] and sim[c][i + sim_begin], i in [real_begin, real_end),
// with each channel's offset profiled out when profile_offsets (offsets receives them,
// one per channel; zeros otherwise).
double PooledError(Metric metric, const Signals& real, const Signals& sim, int64_t real_begin,
                   int64_t real_end, int64_t sim_begin, bool profile_offsets,
                   std::vector<double>* offsets = nullptr);

struct ShiftedError {
  double error = 0;             // pooled over channels at the best shift
  int shift = 0;                // real[i] pairs with sim[i + shift] (samples)
  std::vector<double> offsets;  // per channel at the best shift (real - sim)
};

// Paper 003 eq. 4: the minimum over integer shifts s in [-max_shift, max_shift] of the
// pooled error between real[c][i] and sim[c][i + s] on the overlap (i and i + s both in
// [0, n)); one shift for all channels. Real and sim have the same length n per channel,
// and the overlap must keep at least one sample (max_shift < n). Ties go to the smaller
// |s|, then to the negative one.
ShiftedError ShiftInvariantError(Metric metric, const Signals& real, const Signals& sim,
                                 int max_shift, bool profile_offsets);

// The search behind both: error_at(s, offsets) for s = 0, -1, 1, ..., -max_shift, max_shift;
// the smallest error wins (ties as above). For comparisons that cannot be written as index
// shifts (irregular sampling: the caller interpolates the simulation at shifted times).
ShiftedError MinimumOverShifts(
    int max_shift, const std::function<double(int shift, std::vector<double>* offsets)>& error_at);

// The same with a padded simulation: sim[c] has n + 2 * max_shift samples and real[c][i]
// pairs with sim[c][i + max_shift + s], so every shift compares all n samples.
ShiftedError PaddedShiftInvariantError(Metric metric, const Signals& real, const Signals& sim,
                                       int max_shift, bool profile_offsets);

// Linear interpolation of samples x at strictly increasing times t, at time q; clamped to
// the first and last sample outside [t.front(), t.back()]. Exact at the sample times.
double Interpolate(std::span<const double> t, std::span<const double> x, double q);

// Samples per gait period at sampling interval dt: round(period / dt), at least 2.
int BinsPerPeriod(double period_s, double dt_s);

// The whole gait cycles k (as [begin, end)) whose bins origin + k period + i period / n_bins,
// i in [0, n_bins), all lie within [t_first, t_last] (a tolerance of 1e-6 of a bin allows
// for rounding). Empty (begin == end) when none.
std::pair<int64_t, int64_t> WholeCycles(double t_first, double t_last, double period_s, int n_bins,
                                        double origin_s);

// Period averaging (paper 003, Fig. 4a): the signal (t, x) interpolated at
// origin + k period + i period / n_bins for each cycle k in [k_begin, k_end) and averaged
// over the cycles, for i in [-pad, n_bins + pad): n_bins + 2 pad samples, one period plus
// `pad` bins either side (for shifting). A drifting channel (x of a walking robot) keeps its
// mean drift over the period as a ramp. Empty when k_begin >= k_end.
std::vector<double> PeriodAverage(std::span<const double> t, std::span<const double> x,
                                  double period_s, int n_bins, double origin_s, int64_t k_begin,
                                  int64_t k_end, int pad = 0);

// The same for a signal sampled regularly at dt from its first sample: its whole cycles of
// round(period / dt) samples, cycle k starting at time k * period, averaged into one cycle.
std::vector<double> PeriodAverageSampled(std::span<const double> x, double dt_s, double period_s);

// Least-squares slope of x over t (0 with fewer than two distinct times).
double LeastSquaresSlope(std::span<const double> t, std::span<const double> x);

// The mean of several equally long signals, sample by sample.
std::vector<double> MeanSignal(const Signals& signals);

// Distance per gait cycle of a walking body: the least-squares slope of its position over
// time times the period. Over many cycles it is insensitive to the hops of single cycles.
double DistancePerCycle(std::span<const double> t, std::span<const double> x, double period_s);

}  // namespace gaitforge::calibration
