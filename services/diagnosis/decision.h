// The gap finder's verdict (docs/diagnosis.md, "Decide"): which fitted explanation, if any,
// beats the baseline beyond noise. Pure functions over fit scores, so that the rule is
// tested on its own (tests/unit/cli/diagnosis_decision_test.cc).
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <vector>

namespace gaitforge::diagnosis {

// One fitted explanation: the base model plus `effects` (none: the baseline).
struct FitScore {
  std::vector<std::string> effects;   // catalog ids
  bool ok = false;                    // the fit produced a valid model
  double bic = NAN;                   // on the training error
  double train = NAN;                 // the training error itself
  double held = NAN;                   // held-out error, mean over the numeric variants
  std::vector<double> held_variants;  // held-out error under each numeric variant
  bool at_bound = false;              // an effect parameter at the edge of its range
};

struct DecisionRule {
  double margin = 10;           // BIC margin against the baseline and between explanations
  double held_out_gain = 0.15;  // a discovery cuts the baseline's held-out error this much
  double paired_t = 2.015;      // and wins the paired comparison across variants (one-sided
                                // 5% at 5 degrees of freedom: six variants)
  double pair_gain = 0.05;      // a pair replaces its member only if 5% better held out
  // The index in held_variants of the finest-step numeric variant (-1: none). A pair must
  // beat its member by pair_gain there too: a partner that the model's own step asks for
  // vanishes at a finer one (the walker's 12-14 ms lag beside a deadband or a slope at
  // 0.5 ms against 0.25 ms recordings; both named alone when diagnosed at 0.25 ms).
  int finest_step = -1;
  // The held-out error's own spread under numerically irrelevant variants (the baseline's
  // sd across them): two explanations whose held-out errors differ by less cannot be told
  // apart by the held-out recordings, however consistent the difference (Decide's rival).
  double held_floor = 0;
  // The same on the training recordings (the uncalibrated model's sd across the variants):
  // two passing single effects apart by less on both are a tie, however large the BIC
  // difference (which counts every sample as independent, and a chaotic model's are not).
  double train_floor = 0;
  // How errors read in messages: positions (m) as mm; error = acceleration (relative) as %.
  double error_scale = 1000;
  std::string error_unit = "mm";
  void SetUnitFor(const std::string& error) {
    const bool relative = error == "acceleration";
    error_scale = relative ? 100 : 1000;
    error_unit = relative ? "%" : "mm";
  }
};

struct Decision {
  std::string verdict = "none";  // "found", "ambiguous" or "none"
  std::vector<int> named;        // indices into the fits: the explanation(s), best first
  int remainder_of = -1;         // DecideRequired: the set-aside fit named[0] remains of
};

// How many screened candidates to refit fully: the first `top` of `train` (training errors
// of the valid screening fits, best first), and any after them within `tie` (relative) of
// the last of those, at most `max_extra` more. A short fit orders near ties by chance.
int LeadersToRefit(const std::vector<double>& train, int top, double tie, int max_extra = 2);

// Whether x sits within `fraction` of [lo, hi]'s width from an edge (a zero edge excepted:
// "no effect" is a plausible value). Ranges spanning two decades or more with lo > 0 are
// judged in log space, as their parameters are searched (LogScaled).
bool LogScaled(double lo, double hi);
bool AtBound(double x, double lo, double hi, double fraction = 0.02);

// Paired t statistic of a - b over the variants (positive when b has the lower errors);
// +-infinity when every difference is the same, NAN with fewer than two variants.
double PairedT(const std::vector<double>& a, const std::vector<double>& b);

// The sample standard deviation of v (n - 1 in the denominator); 0 with fewer than two.
double SampleSd(const std::vector<double>& v);

// Whether `fit` beats `base` on every criterion of `rule`. A fit with an effect parameter at
// the edge of its catalog range is no explanation: the data asked for an implausible value,
// the sign of a mismatch the effect only absorbs.
bool BeatsBaseline(const FitScore& base, const FitScore& fit, const DecisionRule& rule);

// structure: joint: the model's structural parameters refitted together (no missing physics
// claimed, only the model's own idealisations corrected) join the baseline when they fit the
// training data better by the BIC margin and predict the held-out recordings no worse than
// the baseline beyond its numeric spread (rule.held_floor).
bool StructureAdmits(const FitScore& base, const FitScore& fit, const DecisionRule& rule);

// Singles are judged first; a fit that contains a passing fit's effects must beat it by the
// margin and by pair_gain held out, and then replaces it. Of the passing explanations the one
// with the lowest held-out error is named. "ambiguous" when another passing single effect is
// within the BIC margin of it, or when a fit with no effect in common (passing or not) beats
// it on training by the margin and is not worse held out by the paired test (t of their
// per-variant differences above -paired_t): then both are named, the passing one first.
// `prefer` (an index, or -1): a fit to name first if it passes, whatever its held-out rank
// (DecideRequired's reduced explanation).
Decision Decide(const FitScore& base, const std::vector<FitScore>& fits, const DecisionRule& rule,
                int prefer = -1);

// Decide, then ask `unneeded(i)` of the first named fit i: which of its effects the data
// do not require (an effect parameter's range holds the value that leaves the model as it
// is, so the model without the effect fits as well). A fit with such an effect is set
// aside, as if it had failed its tests, and the decision taken again, until the first named
// is required or nothing is named. When the fit that remains of the set-aside one without
// its unneeded effects (a pair's other member) passed every test, it is named first: the
// set-aside fit's own evidence is that this member carries the explanation (the verdict's
// `remainder_of` is then that fit). Fills
// `set_aside` (may be null) with the fits set aside, in order.
Decision DecideRequired(const FitScore& base, std::vector<FitScore> fits, const DecisionRule& rule,
                        const std::function<std::vector<std::string>(int)>& unneeded,
                        std::vector<int>* set_aside);

// Of the named explanations of `d`, drops those after the first whose magnitudes the
// training data do not pin (`undetermined[k]` for d.named[k]: an effect parameter's range
// spans most of its allowed values), provided the first is pinned: a fit that is free along
// a whole direction absorbs the mismatch rather than measures an effect, so it is no rival.
// The verdict becomes "found" when one explanation remains. Fills `dropped` (may be null)
// with the dropped fits' indices. The first named is never dropped: it passed every test.
Decision PreferDetermined(const Decision& d, const std::vector<bool>& undetermined,
                          std::vector<int>* dropped);

// Why `fit` was not named, in words for the report: the first test of BeatsBaseline it
// fails, with its figures ("cut the held-out error by only 6% (the rule asks 15%)"); for a
// fit that passed, what the named explanation `winner` (null: none) did better, or, when a
// passing fit among `others` is a member of it that it does not beat by the margins (as
// Decide drops it), that it adds nothing to that member. Empty for the named fit itself.
std::string WhyNotNamed(const FitScore& base, const FitScore& fit, const FitScore* winner,
                        const DecisionRule& rule, const std::vector<const FitScore*>& others = {});

}  // namespace gaitforge::diagnosis
