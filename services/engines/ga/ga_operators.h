#pragma once
// Paper 000's genetic operators as free functions over explicit random streams
// (../shared/papers/, paper 000, section on the GA); they know genes and ranges, no robot.
#include <vector>

#include "services/core/keyed_rng.h"
#include "services/engines/engine.h"

namespace gaitforge::engines::ga {

// Roulette weights: probability proportional to fitness. Roulette needs non-negative
// weights, and distances can be negative, so weights are fitness minus the worst valid
// fitness of the generation (w = f - f_min, "windowing"); the worst member gets weight 0.
// Invalid and infeasible members get 0. If every weight is 0 (all equal, or none valid
// and feasible), the valid feasible members get weight 1, failing that the valid ones,
// failing that all members.
std::vector<double> RouletteWeights(const std::vector<Evaluation>& evals);

// Index i drawn with probability weights[i] / sum(weights). Weights must be non-negative
// with a positive sum.
int RouletteSelect(const std::vector<double>& weights, core::KeyedRng& rng);

// The same draw over prefix sums (cumulative[i] = w[0] + ... + w[i], summed in index
// order), by binary search: one draw consumes one number, exactly like RouletteSelect, and
// picks the same index.
int RouletteSelectCumulative(const std::vector<double>& cumulative, core::KeyedRng& rng);
std::vector<double> Cumulative(const std::vector<double>& weights);

// One-point crossover that swaps the first n genes: child_a = b[0:n] + a[n:],
// child_b = a[0:n] + b[n:].
void SwapPrefix(std::vector<double>& a, std::vector<double>& b, int n);

// Each gene, independently with probability `rate`, becomes a fresh uniform draw in
// [lo, hi). Per gene the stream yields one decision number and, only when the gene
// mutates, one value. Returns how many genes changed.
int MutateReinit(std::vector<double>& genes, const Bounds& bounds, double rate,
                 core::KeyedRng& rng);

}  // namespace gaitforge::engines::ga
