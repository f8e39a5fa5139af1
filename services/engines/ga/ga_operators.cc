#include "services/engines/ga/ga_operators.h"

#include <algorithm>
#include <cmath>
#include <cassert>
#include <limits>

namespace gaitforge::engines::ga {

std::vector<double> RouletteWeights(const std::vector<Evaluation>& evals) {
  double f_min = std::numeric_limits<double>::infinity();
  auto usable = [](const Evaluation& e) { return e.valid && e.violation <= 0.0; };
  for (const auto& e : evals) {
    if (usable(e)) f_min = std::min(f_min, e.fitness);
  }
  std::vector<double> w(evals.size(), 0.0);
  double total = 0.0;
  bool any_valid = false;
  for (size_t i = 0; i < evals.size(); ++i) {
    if (!usable(evals[i])) continue;
    any_valid = true;
    w[i] = evals[i].fitness - f_min;
    total += w[i];
  }
  if (total > 0.0) return w;
  // Nothing usable: fall back to the valid members, then to everyone.
  bool any_plain_valid = false;
  for (const auto& e : evals) any_plain_valid = any_plain_valid || e.valid;
  for (size_t i = 0; i < evals.size(); ++i) {
    if (any_valid) w[i] = usable(evals[i]) ? 1.0 : 0.0;
    else w[i] = (evals[i].valid || !any_plain_valid) ? 1.0 : 0.0;
  }
  return w;
}

int RouletteSelect(const std::vector<double>& weights, core::KeyedRng& rng) {
  double total = 0.0;
  for (double w : weights) total += w;
  const double target = rng.Uniform01() * total;
  double acc = 0.0;
  int last_positive = -1;
  for (size_t i = 0; i < weights.size(); ++i) {
    if (weights[i] <= 0.0) continue;
    acc += weights[i];
    last_positive = static_cast<int>(i);
    if (target < acc) return last_positive;
  }
  return last_positive;  // rounding at the top end
}

std::vector<double> Cumulative(const std::vector<double>& weights) {
  std::vector<double> c(weights.size());
  double acc = 0.0;
  for (size_t i = 0; i < weights.size(); ++i) c[i] = acc += weights[i];
  return c;
}

int RouletteSelectCumulative(const std::vector<double>& cumulative, core::KeyedRng& rng) {
  const double target = rng.Uniform01() * cumulative.back();
  // First index whose prefix sum exceeds the target; zero-weight entries never qualify
  // because their prefix sum equals their predecessor's.
  auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
  if (it == cumulative.end()) {
    // Rounding at the top end: the last entry with positive weight.
    size_t i = cumulative.size() - 1;
    while (i > 0 && cumulative[i] == cumulative[i - 1]) --i;
    return static_cast<int>(i);
  }
  return static_cast<int>(it - cumulative.begin());
}

void SwapPrefix(std::vector<double>& a, std::vector<double>& b, int n) {
  assert(a.size() == b.size());
  for (int i = 0; i < n && i < static_cast<int>(a.size()); ++i) std::swap(a[i], b[i]);
}

int MutateReinit(std::vector<double>& genes, const Bounds& bounds, double rate,
                 core::KeyedRng& rng) {
  int changed = 0;
  for (size_t i = 0; i < genes.size(); ++i) {
    if (rng.Uniform01() < rate) {
      genes[i] = rng.Uniform(bounds.lo[i], bounds.hi[i]);
      ++changed;
    }
  }
  return changed;
}

int TournamentSelect(const std::vector<Evaluation>& evals, int size, core::KeyedRng& rng) {
  const int n = static_cast<int>(evals.size());
  int best = -1;
  for (int k = 0; k < std::max(1, size); ++k) {
    const int pick = std::min(n - 1, static_cast<int>(rng.Uniform01() * n));
    if (best < 0 || RanksBefore(evals[pick], pick, evals[best], best)) best = pick;
  }
  return best;
}

void BlendCrossover(std::vector<double>& a, std::vector<double>& b, const Bounds& bounds,
                    double rate, double alpha, core::KeyedRng& rng) {
  if (!(rng.Uniform01() < rate)) return;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) {
    const double x = a[i], y = bounds.Near(i, b[i], a[i]);
    const double d = std::fabs(x - y), lo = std::min(x, y) - alpha * d, hi = std::max(x, y) + alpha * d;
    a[i] = bounds.Fold(i, d > 0 ? rng.Uniform(lo, hi) : x);
    b[i] = bounds.Fold(i, d > 0 ? rng.Uniform(lo, hi) : y);
  }
}

int MutateGaussian(std::vector<double>& genes, const Bounds& bounds, double rate,
                   double sd_fraction, core::KeyedRng& rng) {
  int changed = 0;
  for (size_t i = 0; i < genes.size(); ++i) {
    if (rng.Uniform01() < rate) {
      genes[i] = bounds.Fold(i, genes[i] + sd_fraction * (bounds.hi[i] - bounds.lo[i]) * rng.Normal());
      ++changed;
    }
  }
  return changed;
}

}  // namespace gaitforge::engines::ga
