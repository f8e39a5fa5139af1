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

// Paper 004's real-coded operators (its arm's fact sheet: tournament of 3, blend crossover
// at rate 0.8, mutation 0.1), the GA's `selection: tournament`, `crossover: blend` and
// `mutation: gaussian`.

// The best of `size` members drawn uniformly with replacement (RanksBefore decides; a tie
// keeps the earlier draw). One number per draw.
int TournamentSelect(const std::vector<Evaluation>& evals, int size, core::KeyedRng& rng);

// BLX-alpha: with probability `rate` (one decision number) each gene of both children is a
// fresh uniform draw in [min - alpha d, max + alpha d] of the parents' values (d = |a - b|,
// on a circular gene the shorter way round), brought into range by Bounds::Fold; otherwise
// the children are the parents.
void BlendCrossover(std::vector<double>& a, std::vector<double>& b, const Bounds& bounds,
                    double rate, double alpha, core::KeyedRng& rng);

// Each gene, independently with probability `rate`, moves by a normal step of sd
// `sd_fraction` of its range, brought into range by Bounds::Fold. Per gene one decision
// number and, only when it mutates, one normal draw. Returns how many genes changed.
int MutateGaussian(std::vector<double>& genes, const Bounds& bounds, double rate,
                   double sd_fraction, core::KeyedRng& rng);

}  // namespace gaitforge::engines::ga
