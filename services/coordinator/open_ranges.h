#pragma once
// What a calibration's recordings leave open (docs/objectives.md, "From a calibration"):
// the parameter values of every evaluation the recordings cannot tell from the best fit.
// A search's final spread says where the search stopped, not what the data pin: five
// recordings over six structural parameters left MuJoCo's fit a CMA-ES spread of 1-10% of
// each value while its held-out recording grew worse (bench/results/transfer-calibrated-*).
#include <cmath>
#include <cstddef>
#include <vector>

#include "storage/study_store.h"

namespace gaitforge::coordinator {

struct GeneRange {
  double lo = NAN, hi = NAN;  // NAN: no range
  bool ok() const { return std::isfinite(lo) && std::isfinite(hi) && lo <= hi; }
};

// The one-sided 95% quantile of Student's t with df >= 1 degrees of freedom.
double StudentT95(int df);

// An evaluation's per-recording errors (metrics error_0 .. error_<n-1>, docs/calibration.md
// "Metrics"); empty when it has none.
std::vector<double> RecordingErrors(const storage::IndividualRecord& r);

// Whether errors x are no worse than best's beyond chance: over n >= 2 recordings the paired
// log ratios d = log(x / best) have mean at most StudentT95(n - 1) sd(d) / sqrt(n). Ratios,
// not differences: recordings' errors differ by an order of magnitude (one gait the model
// misses by 5 mm, another by 0.6), and differences then let the largest decide alone (the
// uncalibrated model passed as no worse than MuJoCo's fit). False when the sizes differ,
// n < 2 or an error is not positive.
bool IndistinguishableFrom(const std::vector<double>& best, const std::vector<double>& x);

// The genes of best, then of every other valid evaluation whose recording errors are
// indistinguishable from best's, in the order given. Empty when best has fewer than two
// recording errors.
std::vector<std::vector<double>> FitsLeftOpen(
    const std::vector<storage::IndividualRecord>& evaluated, const storage::IndividualRecord& best,
    size_t genes);

// Per gene, the extent of the points (as many genes as the first has; empty for none).
std::vector<GeneRange> Extent(const std::vector<std::vector<double>>& points);

// Up to n of `points` spread over the set they fill: the first, then each time the point
// farthest from those chosen (farthest-point order), with distances in units of each
// gene's `scale` range (its logarithm's where `log`). The indices, in that order. A search's
// evaluations crowd where it converged; the set the recordings leave open is all of it.
std::vector<size_t> Cover(const std::vector<std::vector<double>>& points,
                          const std::vector<GeneRange>& scale, const std::vector<bool>& log,
                          size_t n);

// Per gene, the hull of a and b (a gene whose range is missing in one takes the other's).
std::vector<GeneRange> Hull(const std::vector<GeneRange>& a, const std::vector<GeneRange>& b);

}  // namespace gaitforge::coordinator
