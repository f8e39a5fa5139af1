// FloorRange (diagnosis_range.h): the parameter ranges that the training recordings cannot
// tell from the fit, given the model's own numerical spread.
#include "services/diagnosis/range.h"

#include "services/diagnosis/decision.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>

#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "workers/effects/effects.h"

namespace gaitforge::diagnosis {
namespace {

constexpr int kRounds = 4;
constexpr int kPointsPerGene = 20;
constexpr int kEnoughAccepted = 8;
constexpr int kBisections = 5;  // per end of each range: 1/32 of the way to the box
constexpr int kExpansions = 4;  // past an accepted box edge: steps of 1, 2, 4, 8 box widths
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

FitRange SearchRange(const RangeSearch& s, const BatchErrors& errors) {
  FitRange out;
  const size_t k = s.x0.size();
  out.params.resize(k);
  out.tolerance = s.tolerance;
  if (k == 0 || !(s.tolerance > 0)) return out;
  const std::vector<double>&lo = s.lo, &hi = s.hi, &x0 = s.x0;
  std::vector<double> a(k), b(k);
  for (size_t i = 0; i < k; ++i) {
    const double span = kStartSpan * std::max(std::abs(x0[i]), 0.05 * (hi[i] - lo[i]));
    a[i] = std::max(lo[i], x0[i] - span);
    b[i] = std::min(hi[i], x0[i] + span);
  }
  std::mt19937_64 rng(s.seed);
  std::vector<std::vector<double>> xs = {x0};
  std::vector<double> es = errors(xs);
  std::vector<double> acc_lo(k), acc_hi(k);
  for (int round = 0; round < kRounds; ++round) {
    std::vector<std::vector<double>> batch;
    for (size_t p = 0; p < kPointsPerGene * k; ++p) {
      std::vector<double> x(k);
      for (size_t i = 0; i < k; ++i) x[i] = a[i] + (b[i] - a[i]) * Uniform(rng);
      batch.push_back(std::move(x));
    }
    const std::vector<double> e = errors(batch);
    for (size_t p = 0; p < batch.size(); ++p) {
      xs.push_back(batch[p]);
      es.push_back(p < e.size() ? e[p] : NAN);
    }
    out.evaluations = static_cast<int>(xs.size());
    double best = INFINITY;
    for (double v : es)
      if (std::isfinite(v)) best = std::min(best, v);
    if (!std::isfinite(best)) return out;
    out.accepted = 0;
    acc_lo.assign(k, INFINITY);
    acc_hi.assign(k, -INFINITY);
    for (size_t p = 0; p < xs.size(); ++p) {
      if (!(es[p] <= best + s.tolerance)) continue;
      ++out.accepted;
      for (size_t i = 0; i < k; ++i) {
        acc_lo[i] = std::min(acc_lo[i], xs[p][i]);
        acc_hi[i] = std::max(acc_hi[i], xs[p][i]);
      }
    }
    // Where the accepted set meets the box (not a bound of the parameter), the range goes on.
    bool grow = false;
    for (size_t i = 0; i < k; ++i) {
      const double w = b[i] - a[i], edge = 0.1 * w;
      const bool touch_lo = a[i] > lo[i] && acc_lo[i] < a[i] + edge;
      const bool touch_hi = b[i] < hi[i] && acc_hi[i] > b[i] - edge;
      if (touch_lo) a[i] = std::max(lo[i], a[i] - w);
      if (touch_hi) b[i] = std::min(hi[i], b[i] + w);
      grow = grow || touch_lo || touch_hi;
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
  // Random points reach a corner of the accepted set's extent rarely, and the set may go on
  // past the box after the last round: push each end outwards along its axis from the
  // accepted point that holds it (both ends of one parameter in one batch).
  double best = INFINITY;
  for (double v : es)
    if (std::isfinite(v)) best = std::min(best, v);
  std::vector<std::array<bool, 2>> open_end(k, {false, false});
  for (size_t i = 0; i < k; ++i) {
    std::vector<double> in_pt[2], out_pt[2];  // [0] the low end, [1] the high end
    bool active[2];
    for (int side = 0; side < 2; ++side) {
      size_t holder = 0;
      for (size_t p = 0; p < xs.size(); ++p)
        if (es[p] <= best + s.tolerance &&
            (side == 0 ? xs[p][i] < xs[holder][i] : xs[p][i] > xs[holder][i]))
          holder = p;
      in_pt[side] = out_pt[side] = xs[holder];
      out_pt[side][i] = side == 0 ? a[i] : b[i];
      active[side] = out_pt[side][i] != in_pt[side][i];
    }
    // Try the box's edge itself first. Where it is the parameter's bound (often the value at
    // which the effect is absent), bisection alone would never evaluate it and would end 1/32
    // of the way short of a bound the data cannot tell from the fit. Where it is not a bound
    // and is accepted, the range goes on past the box: step on outwards, each step twice the
    // last, until a point is refused (bisection then works between), the bound is reached,
    // or kExpansions steps were all accepted (the range is open on that side).
    bool open[2] = {false, false};
    {
      bool probing[2] = {active[0], active[1]};
      double stride[2] = {-(b[i] - a[i]), b[i] - a[i]};  // the box's width, then doubling
      for (int step = 0; step <= kExpansions && (probing[0] || probing[1]); ++step) {
        std::vector<std::vector<double>> batch;
        std::vector<int> sides;
        for (int side = 0; side < 2; ++side)
          if (probing[side]) {
            batch.push_back(out_pt[side]);
            sides.push_back(side);
          }
        const std::vector<double> e = errors(batch);
        out.evaluations += static_cast<int>(batch.size());
        for (size_t q = 0; q < batch.size(); ++q) {
          const int side = sides[q];
          if (!(q < e.size() && e[q] <= best + s.tolerance)) {
            probing[side] = false;  // refused: bisect between the last accepted and here
            continue;
          }
          ++out.accepted;
          in_pt[side] = out_pt[side];
          const double bound = side == 0 ? lo[i] : hi[i];
          if (in_pt[side][i] == bound || step == kExpansions) {
            probing[side] = active[side] = false;
            open[side] = in_pt[side][i] != bound;
            continue;
          }
          out_pt[side][i] = std::clamp(in_pt[side][i] + stride[side], lo[i], hi[i]);
          stride[side] *= 2;
        }
      }
    }
    for (int step = 0; step < kBisections && (active[0] || active[1]); ++step) {
      std::vector<std::vector<double>> batch;
      std::vector<int> sides;
      for (int side = 0; side < 2; ++side) {
        if (!active[side]) continue;
        std::vector<double> mid = in_pt[side];
        mid[i] = 0.5 * (in_pt[side][i] + out_pt[side][i]);
        batch.push_back(std::move(mid));
        sides.push_back(side);
      }
      const std::vector<double> e = errors(batch);
      out.evaluations += static_cast<int>(batch.size());
      for (size_t q = 0; q < batch.size(); ++q) {
        const bool ok = q < e.size() && e[q] <= best + s.tolerance;
        (ok ? in_pt : out_pt)[sides[q]] = batch[q];
        out.accepted += ok;
      }
    }
    acc_lo[i] = std::min(acc_lo[i], in_pt[0][i]);
    acc_hi[i] = std::max(acc_hi[i], in_pt[1][i]);
    open_end[i] = {open[0], open[1]};
  }
  for (size_t i = 0; i < k; ++i) {
    ParamRange& r = out.params[i];
    r.open_lo = open_end[i][0];
    r.open_hi = open_end[i][1];
    r.lo = r.open_lo ? NAN : std::min(acc_lo[i], x0[i]);  // the fit stays in its range
    r.hi = r.open_hi ? NAN : std::max(acc_hi[i], x0[i]);
  }
  return out;
}

double RangeShare(const ParamRange& r, double lo, double hi) {
  const bool has_lo = r.open_lo || std::isfinite(r.lo), has_hi = r.open_hi || std::isfinite(r.hi);
  if (!has_lo || !has_hi || !(hi > lo)) return NAN;
  double a = r.open_lo ? lo : std::clamp(r.lo, lo, hi), b = r.open_hi ? hi : std::clamp(r.hi, lo, hi);
  if (LogScaled(lo, hi)) {
    a = std::log(a);
    b = std::log(b);
    lo = std::log(lo);
    hi = std::log(hi);
  }
  return (b - a) / (hi - lo);
}

bool RangeHolds(const ParamRange& r, double x, double lo, double hi) {
  const double a = r.open_lo ? lo : r.lo, b = r.open_hi ? hi : r.hi;
  return a <= x && x <= b;  // false with a NAN end
}

RangeVerdict JudgeRange(const Candidate& c, const FitRange& r, size_t first_effect_gene) {
  std::vector<std::string> loose, unneeded, ids;
  auto end = [](double v, bool open, double bound) {
    return absl::StrFormat("%.3g%s", open ? bound : v, open ? " (open)" : "");
  };
  // Per effect: the words for each of its genes whose range holds the nominal, and whether
  // one of its genes' ranges does not (then the model without the effect is refused).
  std::vector<std::string> order;
  std::map<std::string, std::pair<std::vector<std::string>, bool>> held;
  for (size_t i = first_effect_gene; i < c.genes.size() && i < r.params.size(); ++i) {
    const auto& g = c.genes[i];
    if (g.name().rfind("nuisance.", 0) == 0) continue;
    const ParamRange& p = r.params[i];
    const double share = RangeShare(p, g.lo(), g.hi());
    if (share >= kUndeterminedShare)
      loose.push_back(absl::StrFormat("%s (%.0f%%)", g.name(), 100 * share));
    // The effect's gene at its nominal value: the effect absent (Make), wherever the fit
    // started.
    if (i >= c.gene_effect.size() || c.gene_effect[i].empty() || i >= c.nominal.size()) continue;
    const std::string& id = c.gene_effect[i];
    if (!held.count(id)) order.push_back(id);
    auto& [words, refused] = held[id];
    const double nominal = c.nominal[i];
    if (!RangeHolds(p, nominal, g.lo(), g.hi())) {
      refused = true;
      continue;
    }
    words.push_back(absl::StrFormat("%s's range %s .. %s holds %g", g.name(),
                                    end(p.lo, p.open_lo, g.lo()), end(p.hi, p.open_hi, g.hi()),
                                    nominal));
  }
  for (const std::string& id : order) {
    const auto& [words, refused] = held[id];
    if (refused) continue;
    ids.push_back(id);
    unneeded.insert(unneeded.end(), words.begin(), words.end());
  }
  return {absl::StrJoin(loose, ", "), absl::StrJoin(unneeded, "; "), ids};
}

FitRange FloorRange(const Candidate& c, const v1::DiagnosisSpec& d,
                    const std::vector<std::string>& train_files,
                    const std::vector<double>& weights, double tolerance, uint64_t seed) {
  std::vector<size_t> fit;
  for (size_t i = 0; i < c.genes.size() && i < c.values.size(); ++i)
    if (c.genes[i].name().rfind("nuisance.", 0) != 0) fit.push_back(i);
  RangeSearch s;
  s.tolerance = tolerance;
  s.seed = seed;
  for (size_t i : fit) {
    s.lo.push_back(c.genes[i].lo());
    s.hi.push_back(c.genes[i].hi());
    s.x0.push_back(c.values[i]);
  }
  // Two at a time: each point is one gaitforge-sim process over the training files.
  auto errors = [&](const std::vector<std::vector<double>>& points) {
    std::vector<double> e(points.size(), NAN);
    TwoAtATime(points.size(), [&](size_t p) {
      e[p] = WeightedError(c, fit, points[p], d, train_files, weights);
    });
    return e;
  };
  const FitRange found = SearchRange(s, errors);
  FitRange out = found;  // per gene of c: nuisances NAN
  out.params.assign(c.genes.size(), ParamRange{});
  for (size_t i = 0; i < fit.size() && i < found.params.size(); ++i)
    out.params[fit[i]] = found.params[i];
  return out;
}

}  // namespace gaitforge::diagnosis
