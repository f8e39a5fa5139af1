#include "services/coordinator/open_ranges.h"

#include <algorithm>
#include <string>

namespace gaitforge::coordinator {

double StudentT95(int df) {
  static const double table[] = {6.314, 2.920, 2.353, 2.132, 2.015, 1.943, 1.895, 1.860,
                                 1.833, 1.812, 1.796, 1.782, 1.771, 1.761, 1.753, 1.746,
                                 1.740, 1.734, 1.729, 1.725, 1.721, 1.717, 1.714, 1.711,
                                 1.708, 1.706, 1.703, 1.701, 1.699, 1.697};
  constexpr int kTable = sizeof(table) / sizeof(table[0]);
  if (df < 1) return NAN;
  if (df <= kTable) return table[df - 1];
  const double z = 1.6449;  // the normal quantile with the first correction term
  return z + (z * z * z + z) / (4.0 * df);
}

std::vector<double> RecordingErrors(const storage::IndividualRecord& r) {
  std::vector<double> out;
  for (;;) {
    auto it = r.metrics.find("error_" + std::to_string(out.size()));
    if (it == r.metrics.end()) return out;
    out.push_back(it->second);
  }
}

bool IndistinguishableFrom(const std::vector<double>& best, const std::vector<double>& x) {
  const size_t n = best.size();
  if (n < 2 || x.size() != n) return false;
  std::vector<double> d(n);
  for (size_t i = 0; i < n; ++i) {
    if (!(best[i] > 0) || !(x[i] > 0)) return false;
    d[i] = std::log(x[i] / best[i]);
  }
  double mean = 0;
  for (double v : d) mean += v / n;
  double ss = 0;
  for (double v : d) ss += (v - mean) * (v - mean);
  const double sd = std::sqrt(ss / (n - 1));
  if (!std::isfinite(mean) || !std::isfinite(sd)) return false;
  return mean <= StudentT95(static_cast<int>(n) - 1) * sd / std::sqrt(static_cast<double>(n));
}

std::vector<std::vector<double>> FitsLeftOpen(
    const std::vector<storage::IndividualRecord>& evaluated, const storage::IndividualRecord& best,
    size_t genes) {
  const std::vector<double> reference = RecordingErrors(best);
  if (reference.size() < 2 || best.genes.size() != genes) return {};
  std::vector<std::vector<double>> out = {best.genes};
  for (const auto& r : evaluated) {
    if (!r.valid || r.genes.size() != genes) continue;
    if (r.generation == best.generation && r.member == best.member) continue;
    if (IndistinguishableFrom(reference, RecordingErrors(r))) out.push_back(r.genes);
  }
  return out;
}

std::vector<GeneRange> Extent(const std::vector<std::vector<double>>& points) {
  std::vector<GeneRange> out(points.empty() ? 0 : points[0].size());
  for (const auto& x : points)
    for (size_t g = 0; g < out.size() && g < x.size(); ++g)
      out[g] = out[g].ok() ? GeneRange{std::min(out[g].lo, x[g]), std::max(out[g].hi, x[g])}
                           : GeneRange{x[g], x[g]};
  return out;
}

std::vector<size_t> Cover(const std::vector<std::vector<double>>& points,
                          const std::vector<GeneRange>& scale, const std::vector<bool>& log,
                          size_t n) {
  // Coordinates in units of each gene's range (its logarithm's for a log gene).
  auto coord = [&](double x, size_t g) {
    const bool ln = g < log.size() && log[g] && scale[g].lo > 0 && x > 0;
    const double lo = ln ? std::log(scale[g].lo) : scale[g].lo;
    const double hi = ln ? std::log(scale[g].hi) : scale[g].hi;
    return hi > lo ? ((ln ? std::log(x) : x) - lo) / (hi - lo) : 0.0;
  };
  auto distance2 = [&](const std::vector<double>& a, const std::vector<double>& b) {
    double d2 = 0;
    for (size_t g = 0; g < scale.size() && g < a.size() && g < b.size(); ++g) {
      const double d = coord(a[g], g) - coord(b[g], g);
      d2 += d * d;
    }
    return d2;
  };
  std::vector<double> nearest(points.size(), INFINITY);
  std::vector<size_t> out;
  for (size_t next = 0; !points.empty() && out.size() < std::min(n, points.size());) {
    out.push_back(next);
    for (size_t i = 0; i < points.size(); ++i)
      nearest[i] = std::min(nearest[i], distance2(points[i], points[next]));
    next = std::max_element(nearest.begin(), nearest.end()) - nearest.begin();
    if (!(nearest[next] > 0)) break;  // the rest repeat chosen points
  }
  return out;
}

std::vector<GeneRange> Hull(const std::vector<GeneRange>& a, const std::vector<GeneRange>& b) {
  std::vector<GeneRange> out(std::max(a.size(), b.size()));
  for (size_t g = 0; g < out.size(); ++g) {
    const GeneRange x = g < a.size() ? a[g] : GeneRange{};
    const GeneRange y = g < b.size() ? b[g] : GeneRange{};
    if (!x.ok()) out[g] = y;
    else if (!y.ok()) out[g] = x;
    else out[g] = {std::min(x.lo, y.lo), std::max(x.hi, y.hi)};
  }
  return out;
}

}  // namespace gaitforge::coordinator
