// The uncertainty of a fitted explanation's parameters that the gap finder reports: the
// range of each parameter over which the training error stays within the chaos floor of its
// best value (docs/diagnosis.md, "The range of a fitted magnitude").
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "services/diagnosis/fits.h"
#include "gaitforge/v1/diagnosis.pb.h"

namespace gaitforge::diagnosis {

struct ParamRange {
  double lo = NAN, hi = NAN;             // NAN: not bounded within the search on that side
  bool open_lo = false, open_hi = false;  // steps past the box found no end there
};

struct FitRange {
  std::vector<ParamRange> params;  // one per gene of the candidate; nuisances left NAN
  double tolerance = NAN;          // the floor of the weighted training error (m)
  int evaluations = 0;             // training evaluations spent
  int accepted = 0;                // of them within the tolerance
};

// The share of a parameter's allowed values [lo, hi] that its range r spans (an open side
// reaches the bound), in log space when lo > 0 and hi >= 100 lo (as AtBound judges them).
// NAN when r holds no range. At kUndeterminedShare or more the data do not pin the
// parameter: it is undetermined.
double RangeShare(const ParamRange& r, double lo, double hi);
inline constexpr double kUndeterminedShare = 0.9;

// Whether r holds x (an open side reaches the bound lo or hi); false when r holds no range.
bool RangeHolds(const ParamRange& r, double x, double lo, double hi);

// What a fitted explanation's ranges say of it, in words for the report ("" when nothing):
// `loose`, its effect parameters that are not pinned (RangeShare at kUndeterminedShare or
// more); `unneeded`, the parameters of each effect the data do not require: every one of the
// effect's parameters has a range that holds the value that leaves the model as it is
// (effects::EffectInfo::Param::nominal), so the model without the effect fits as well. An
// effect with one parameter refused at its nominal (a friction with its forward coefficient
// pinned away from the model's) is required, whatever its other parameters' ranges hold.
// Genes before `first_effect_gene` (the base parameters) and nuisances are not judged.
struct RangeVerdict {
  std::string loose, unneeded;
  std::vector<std::string> unneeded_effects;  // the ids of the effects `unneeded` names
};
RangeVerdict JudgeRange(const Candidate& c, const FitRange& r, size_t first_effect_gene);

// The floor of the weighted training error: the spread of sum_f w_f e_f / n when each
// file's error e_f varies by its floor (sd over the numeric variants), files independent.
double TrainingTolerance(const std::vector<double>& weights, const std::vector<double>& floors);

// The search itself, on any error function: points x (one value per parameter, within
// [lo, hi]) go to `errors` in batches, which returns one error each (NAN: failed). x0 is the
// fit. Returns the range of each parameter, the evaluations and the accepted count.
struct RangeSearch {
  std::vector<double> lo, hi, x0;
  double tolerance = NAN;
  uint64_t seed = 0;
};
using BatchErrors =
    std::function<std::vector<double>(const std::vector<std::vector<double>>& points)>;
FitRange SearchRange(const RangeSearch& s, const BatchErrors& errors);

// Samples c's non-nuisance genes in a box around the fit (the time offset held at its fit)
// and keeps the points whose weighted training error is within `tolerance` of the least
// found; the box shrinks onto a small accepted set and grows where the set touches it
// (never past a gene's bounds), for at most 4 rounds of 20 points per gene; then each end
// is pushed outwards along its axis: the box's edge is tried, and where it is accepted steps
// of 1, 2, 4, 8 box widths go on past it until one is refused, then 5 bisections between.
// Deterministic for a given seed. Evaluations run two at a time (gaitforge-sim
// calibration-eval).
FitRange FloorRange(const Candidate& c, const v1::DiagnosisSpec& d,
                    const std::vector<std::string>& train_files,
                    const std::vector<double>& weights, double tolerance, uint64_t seed);

}  // namespace gaitforge::diagnosis
