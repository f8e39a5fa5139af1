#include "workers/objectives/calibration_error.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "absl/strings/str_cat.h"

namespace gaitforge::calibration {

absl::StatusOr<Metric> ParseMetric(std::string_view name) {
  if (name == "rmse") return Metric::kRmse;
  if (name == "mae") return Metric::kMae;
  return absl::InvalidArgumentError(
      absl::StrCat("unknown metric '", std::string(name), "'; expected rmse or mae"));
}

double Mae(std::span<const double> a, std::span<const double> b) {
  const size_t n = std::min(a.size(), b.size());
  if (n == 0) return 0;
  double sum = 0;
  for (size_t i = 0; i < n; ++i) sum += std::fabs(a[i] - b[i]);
  return sum / static_cast<double>(n);
}

double Rmse(std::span<const double> a, std::span<const double> b) {
  const size_t n = std::min(a.size(), b.size());
  if (n == 0) return 0;
  double sum = 0;
  for (size_t i = 0; i < n; ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(sum / static_cast<double>(n));
}

double Error(Metric metric, std::span<const double> a, std::span<const double> b) {
  return metric == Metric::kRmse ? Rmse(a, b) : Mae(a, b);
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0;
  const size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + mid, v.end());
  const double upper = v[mid];
  if (v.size() % 2 == 1) return upper;
  const double lower = *std::max_element(v.begin(), v.begin() + mid);
  return 0.5 * (lower + upper);
}

namespace {

// Offset of residuals r: mean (RMSE) or median (MAE).
double OffsetOf(Metric metric, const std::vector<double>& r) {
  if (r.empty()) return 0;
  if (metric == Metric::kMae) return Median(r);
  double sum = 0;
  for (double v : r) sum += v;
  return sum / static_cast<double>(r.size());
}

}  // namespace

double ProfiledOffset(Metric metric, std::span<const double> real, std::span<const double> sim) {
  const size_t n = std::min(real.size(), sim.size());
  std::vector<double> r(n);
  for (size_t i = 0; i < n; ++i) r[i] = real[i] - sim[i];
  return OffsetOf(metric, r);
}

double PooledError(Metric metric, const Signals& real, const Signals& sim, int64_t real_begin,
                   int64_t real_end, int64_t sim_begin, bool profile_offsets,
                   std::vector<double>* offsets) {
  if (offsets) offsets->assign(real.size(), 0.0);
  double sum = 0;
  int64_t count = 0;
  std::vector<double> r;
  for (size_t c = 0; c < real.size() && c < sim.size(); ++c) {
    const int64_t lo = std::max<int64_t>(real_begin, std::max<int64_t>(0, -sim_begin));
    const int64_t hi = std::min<int64_t>({real_end, static_cast<int64_t>(real[c].size()),
                                          static_cast<int64_t>(sim[c].size()) - sim_begin});
    r.clear();
    for (int64_t i = lo; i < hi; ++i) r.push_back(real[c][i] - sim[c][i + sim_begin]);
    const double offset = profile_offsets ? OffsetOf(metric, r) : 0.0;
    if (offsets) (*offsets)[c] = offset;
    for (double v : r) {
      const double e = v - offset;
      sum += metric == Metric::kRmse ? e * e : std::fabs(e);
    }
    count += static_cast<int64_t>(r.size());
  }
  if (count == 0) return 0;
  const double mean = sum / static_cast<double>(count);
  return metric == Metric::kRmse ? std::sqrt(mean) : mean;
}

// Shifts 0, -1, 1, -2, 2, ...: a strictly smaller error wins, so ties go to the smaller
// |s| and then to the negative one.
ShiftedError MinimumOverShifts(
    int max_shift, const std::function<double(int shift, std::vector<double>* offsets)>& error_at) {
  ShiftedError best;
  bool first = true;
  auto consider = [&](int s) {
    std::vector<double> offsets;
    const double e = error_at(s, &offsets);
    if (first || e < best.error) {
      best.error = e;
      best.shift = s;
      best.offsets = std::move(offsets);
      first = false;
    }
  };
  consider(0);
  for (int m = 1; m <= max_shift; ++m) {
    consider(-m);
    consider(m);
  }
  return best;
}

namespace {

int64_t Length(const Signals& s) { return s.empty() ? 0 : static_cast<int64_t>(s[0].size()); }

}  // namespace

ShiftedError ShiftInvariantError(Metric metric, const Signals& real, const Signals& sim,
                                 int max_shift, bool profile_offsets) {
  const int64_t n = std::min(Length(real), Length(sim));
  max_shift = static_cast<int>(std::clamp<int64_t>(max_shift, 0, std::max<int64_t>(0, n - 1)));
  return MinimumOverShifts(max_shift, [&](int s, std::vector<double>* offsets) {
    const int64_t lo = std::max<int64_t>(0, -s), hi = std::min<int64_t>(n, n - s);
    return PooledError(metric, real, sim, lo, hi, s, profile_offsets, offsets);
  });
}

ShiftedError PaddedShiftInvariantError(Metric metric, const Signals& real, const Signals& sim,
                                       int max_shift, bool profile_offsets) {
  const int64_t n = Length(real);
  max_shift = std::max(0, max_shift);
  return MinimumOverShifts(max_shift, [&](int s, std::vector<double>* offsets) {
    return PooledError(metric, real, sim, 0, n, max_shift + s, profile_offsets, offsets);
  });
}

double Interpolate(std::span<const double> t, std::span<const double> x, double q) {
  const size_t n = std::min(t.size(), x.size());
  if (n == 0) return 0;
  if (!(q > t[0])) return x[0];
  if (!(q < t[n - 1])) return x[n - 1];
  const size_t hi = static_cast<size_t>(std::upper_bound(t.begin(), t.begin() + n, q) - t.begin());
  const size_t lo = hi - 1;
  const double w = (q - t[lo]) / (t[hi] - t[lo]);
  return x[lo] + w * (x[hi] - x[lo]);
}

int BinsPerPeriod(double period_s, double dt_s) {
  const double n = std::round(period_s / dt_s);
  return n < 2 || !std::isfinite(n) ? 2 : static_cast<int>(n);
}

std::pair<int64_t, int64_t> WholeCycles(double t_first, double t_last, double period_s, int n_bins,
                                        double origin_s) {
  const double tol = 1e-6 / n_bins;  // in cycles
  const double bin = period_s / n_bins;
  const int64_t begin = static_cast<int64_t>(std::ceil((t_first - origin_s) / period_s - tol));
  // The last bin of cycle k is at origin + (k + 1) period - bin.
  const int64_t end = static_cast<int64_t>(std::floor((t_last - origin_s + bin) / period_s + tol));
  return {begin, std::max(begin, end)};
}

std::vector<double> PeriodAverage(std::span<const double> t, std::span<const double> x,
                                  double period_s, int n_bins, double origin_s, int64_t k_begin,
                                  int64_t k_end, int pad) {
  if (k_begin >= k_end || n_bins < 1) return {};
  pad = std::max(0, pad);
  const double bin = period_s / n_bins;
  std::vector<double> avg(n_bins + 2 * pad, 0.0);
  for (int64_t k = k_begin; k < k_end; ++k) {
    const double start = origin_s + static_cast<double>(k) * period_s;
    for (int i = -pad; i < n_bins + pad; ++i) {
      avg[i + pad] += Interpolate(t, x, start + i * bin);
    }
  }
  for (double& v : avg) v /= static_cast<double>(k_end - k_begin);
  return avg;
}

std::vector<double> PeriodAverageSampled(std::span<const double> x, double dt_s, double period_s) {
  if (x.empty()) return {};
  std::vector<double> t(x.size());
  for (size_t i = 0; i < t.size(); ++i) t[i] = static_cast<double>(i) * dt_s;
  const int n = BinsPerPeriod(period_s, dt_s);
  const auto [kb, ke] = WholeCycles(t.front(), t.back(), period_s, n, 0.0);
  return PeriodAverage(t, x, period_s, n, 0.0, kb, ke);
}

double LeastSquaresSlope(std::span<const double> t, std::span<const double> x) {
  const size_t n = std::min(t.size(), x.size());
  if (n < 2) return 0;
  double mt = 0, mx = 0;
  for (size_t i = 0; i < n; ++i) {
    mt += t[i];
    mx += x[i];
  }
  mt /= static_cast<double>(n);
  mx /= static_cast<double>(n);
  double stt = 0, stx = 0;
  for (size_t i = 0; i < n; ++i) {
    stt += (t[i] - mt) * (t[i] - mt);
    stx += (t[i] - mt) * (x[i] - mx);
  }
  return stt > 0 ? stx / stt : 0;
}

std::vector<double> MeanSignal(const Signals& signals) {
  if (signals.empty()) return {};
  std::vector<double> mean(signals[0].size(), 0.0);
  for (const auto& s : signals) {
    for (size_t i = 0; i < mean.size() && i < s.size(); ++i) mean[i] += s[i];
  }
  for (double& v : mean) v /= static_cast<double>(signals.size());
  return mean;
}

double DistancePerCycle(std::span<const double> t, std::span<const double> x, double period_s) {
  return LeastSquaresSlope(t, x) * period_s;
}

}  // namespace gaitforge::calibration
