#include "services/engines/ga/ga_operators.h"

#include <algorithm>
#include <cassert>
#include <limits>

namespace gaitforge::engines::ga {

std::vector<double> RouletteWeights(const std::vector<Evaluation>& evals) {
  double f_min = std::numeric_limits<double>::infinity();
  for (const auto& e : evals) {
    if (e.valid) f_min = std::min(f_min, e.fitness);
  }
  std::vector<double> w(evals.size(), 0.0);
  double total = 0.0;
  bool any_valid = false;
  for (size_t i = 0; i < evals.size(); ++i) {
    if (!evals[i].valid) continue;
    any_valid = true;
    w[i] = evals[i].fitness - f_min;
    total += w[i];
  }
  if (total > 0.0) return w;
  for (size_t i = 0; i < evals.size(); ++i) w[i] = (evals[i].valid || !any_valid) ? 1.0 : 0.0;
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

void SwapPrefix(std::vector<double>& a, std::vector<double>& b, int n) {
  assert(a.size() == b.size());
  for (int i = 0; i < n && i < static_cast<int>(a.size()); ++i) std::swap(a[i], b[i]);
}

int MutateReinit(std::vector<double>& genes, const Bounds& bounds, double rate,
                 core::KeyedRng& rng) {
  int changed = 0;
  for (size_t i = 0; i < genes.size(); ++i) {
    // Two draws per gene, always, so the stream position never depends on earlier outcomes.
    const double u = rng.Uniform01();
    const double fresh = rng.Uniform(bounds.lo[i], bounds.hi[i]);
    if (u < rate) {
      genes[i] = fresh;
      ++changed;
    }
  }
  return changed;
}

}  // namespace gaitforge::engines::ga
