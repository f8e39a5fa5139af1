// Paper 004's acceleration fitness (acceleration_error.h).
#include "workers/objectives/acceleration_error.h"

#include <cmath>
#include <limits>

namespace gaitforge::calibration {

// The least-squares quadratic (or cubic: the odd term does not change it) through 2m + 1
// samples at i = -m..m has second derivative sum_i w_i x_i / dt^2 with
// w_i = 30 (3 i^2 - m (m + 1)) / (m (m + 1) (2m - 1) (2m + 1) (2m + 3)).
std::vector<double> SavitzkyGolaySecondDerivative(std::span<const double> x, double dt,
                                                  int half_window) {
  const int m = half_window;
  const int64_t n = static_cast<int64_t>(x.size());
  std::vector<double> out(x.size(), std::numeric_limits<double>::quiet_NaN());
  if (m < 2 || !(dt > 0)) return out;
  const double mm = static_cast<double>(m) * (m + 1);
  const double norm = mm * (2.0 * m - 1) * (2.0 * m + 1) * (2.0 * m + 3) * dt * dt / 30.0;
  std::vector<double> w(2 * m + 1);
  for (int i = -m; i <= m; ++i) w[i + m] = (3.0 * i * i - mm) / norm;
  for (int64_t k = m; k + m < n; ++k) {
    double sum = 0;
    for (int i = -m; i <= m; ++i) sum += w[i + m] * x[k + i];
    out[k] = sum;
  }
  return out;
}

double RelativeAccelerationError(Metric metric, const std::vector<Vectors>& real,
                                 const std::vector<Vectors>& sim, int64_t begin, int64_t end) {
  double diff = 0, size = 0;
  for (size_t p = 0; p < real.size() && p < sim.size(); ++p) {
    for (int64_t i = begin; i < end; ++i) {
      double d2 = 0, a2 = 0;
      bool ok = true;
      for (size_t a = 0; a < real[p].size(); ++a) {
        const double r = real[p][a][i], s = sim[p][a][i];
        ok = ok && std::isfinite(r) && std::isfinite(s);
        d2 += (s - r) * (s - r);
        a2 += r * r;
      }
      if (!ok) continue;
      diff += metric == Metric::kMae ? std::sqrt(d2) : d2;
      size += metric == Metric::kMae ? std::sqrt(a2) : a2;
    }
  }
  if (!(size > 0)) return -1;
  return metric == Metric::kMae ? diff / size : std::sqrt(diff / size);
}

}  // namespace gaitforge::calibration
