// FloorRange (diagnosis_range.h): the parameter ranges that the training recordings cannot
// tell from the fit, given the model's own numerical spread.
#include "clients/cli/diagnosis_range.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <thread>

#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"

namespace gaitforge::cli::diagnosis {
namespace {

constexpr int kRounds = 4;
constexpr int kPointsPerGene = 20;
constexpr int kEnoughAccepted = 8;
constexpr double kStartSpan = 0.3;  // of |value| (at least 5% of the gene's range)

// Uniform in [0, 1) from 53 bits: the same on every platform (std distributions are not).
double Uniform(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

// The weighted training error of c with its fitted genes replaced by x at `fit`; NAN when
// the model fails on a file.
double WeightedError(const Candidate& c, const std::vector<size_t>& fit,
                     const std::vector<double>& x, const v1::DiagnosisSpec& d,
                     const std::vector<std::string>& files, const std::vector<double>& weights) {
  Candidate at = c;
  for (size_t i = 0; i < fit.size(); ++i) at.values[fit[i]] = x[i];
  const std::vector<double> e = FileErrors(at, files, d, "");
  if (e.size() != files.size()) return NAN;
  double sum = 0;
  for (size_t f = 0; f < e.size(); ++f) sum += (weights.empty() ? 1.0 : weights[f]) * e[f];
  return sum / e.size();
}

}  // namespace

double TrainingTolerance(const std::vector<double>& weights, const std::vector<double>& floors) {
  if (floors.empty()) return NAN;
  double sq = 0;
  const double n = static_cast<double>(floors.size());
  for (size_t f = 0; f < floors.size(); ++f) {
    const double w = f < weights.size() ? weights[f] : 1.0;
    sq += (w / n) * (w / n) * floors[f] * floors[f];
  }
  return std::sqrt(sq);
}

FitRange FloorRange(const Candidate& c, const v1::DiagnosisSpec& d,
                    const std::vector<std::string>& train_files,
                    const std::vector<double>& weights, double tolerance, uint64_t seed) {
  FitRange out;
  out.params.resize(c.genes.size());
  out.tolerance = tolerance;
  std::vector<size_t> fit;
  for (size_t i = 0; i < c.genes.size() && i < c.values.size(); ++i)
    if (c.genes[i].name().rfind("nuisance.", 0) != 0) fit.push_back(i);
  if (fit.empty() || !(tolerance > 0)) return out;
  const size_t k = fit.size();
  std::vector<double> lo(k), hi(k), x0(k), a(k), b(k);
  for (size_t i = 0; i < k; ++i) {
    const auto& g = c.genes[fit[i]];
    lo[i] = g.lo();
    hi[i] = g.hi();
    x0[i] = c.values[fit[i]];
    const double span = kStartSpan * std::max(std::abs(x0[i]), 0.05 * (hi[i] - lo[i]));
    a[i] = std::max(lo[i], x0[i] - span);
    b[i] = std::min(hi[i], x0[i] + span);
  }
  std::mt19937_64 rng(seed);
  std::vector<std::vector<double>> xs = {x0};
  std::vector<double> es = {WeightedError(c, fit, x0, d, train_files, weights)};
  ++out.evaluations;
  std::vector<double> acc_lo(k), acc_hi(k);
  std::vector<bool> touch_lo(k), touch_hi(k);
  for (int round = 0; round < kRounds; ++round) {
    const size_t first = xs.size();
    for (size_t p = 0; p < kPointsPerGene * k; ++p) {
      std::vector<double> x(k);
      for (size_t i = 0; i < k; ++i) x[i] = a[i] + (b[i] - a[i]) * Uniform(rng);
      xs.push_back(std::move(x));
    }
    es.resize(xs.size(), NAN);
    for (size_t p = first; p < xs.size(); p += 2) {
      std::thread t;
      if (p + 1 < xs.size())
        t = std::thread([&, p] {
          es[p + 1] = WeightedError(c, fit, xs[p + 1], d, train_files, weights);
        });
      es[p] = WeightedError(c, fit, xs[p], d, train_files, weights);
      if (t.joinable()) t.join();
    }
    out.evaluations = static_cast<int>(xs.size());
    double best = INFINITY;
    for (double e : es)
      if (std::isfinite(e)) best = std::min(best, e);
    if (!std::isfinite(best)) return out;
    out.accepted = 0;
    acc_lo.assign(k, INFINITY);
    acc_hi.assign(k, -INFINITY);
    for (size_t p = 0; p < xs.size(); ++p) {
      if (!(es[p] <= best + tolerance)) continue;
      ++out.accepted;
      for (size_t i = 0; i < k; ++i) {
        acc_lo[i] = std::min(acc_lo[i], xs[p][i]);
        acc_hi[i] = std::max(acc_hi[i], xs[p][i]);
      }
    }
    // Where the accepted set meets the box (not a bound of the gene), the range goes on.
    bool grow = false;
    for (size_t i = 0; i < k; ++i) {
      const double w = b[i] - a[i], edge = 0.1 * w;
      touch_lo[i] = a[i] > lo[i] && acc_lo[i] < a[i] + edge;
      touch_hi[i] = b[i] < hi[i] && acc_hi[i] > b[i] - edge;
      if (touch_lo[i]) a[i] = std::max(lo[i], a[i] - w);
      if (touch_hi[i]) b[i] = std::min(hi[i], b[i] + w);
      grow = grow || touch_lo[i] || touch_hi[i];
    }
    if (round + 1 == kRounds) break;
    if (!grow && out.accepted >= kEnoughAccepted) break;
    if (!grow) {
      // Few points inside: sample again, closer around them.
      for (size_t i = 0; i < k; ++i) {
        const double w = acc_hi[i] - acc_lo[i];
        const double pad = std::max(0.5 * w, 0.05 * (b[i] - a[i]));
        a[i] = std::max(lo[i], acc_lo[i] - pad);
        b[i] = std::min(hi[i], acc_hi[i] + pad);
      }
    }
  }
  for (size_t i = 0; i < k; ++i) {
    ParamRange& r = out.params[fit[i]];
    acc_lo[i] = std::min(acc_lo[i], x0[i]);  // the fit itself stays in its range
    acc_hi[i] = std::max(acc_hi[i], x0[i]);
    r.open_lo = touch_lo[i];
    r.open_hi = touch_hi[i];
    r.lo = r.open_lo ? NAN : acc_lo[i];
    r.hi = r.open_hi ? NAN : acc_hi[i];
  }
  return out;
}

}  // namespace gaitforge::cli::diagnosis
