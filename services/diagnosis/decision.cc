#include "services/diagnosis/decision.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"

namespace gaitforge::diagnosis {

double PairedT(const std::vector<double>& a, const std::vector<double>& b) {
  const size_t n = std::min(a.size(), b.size());
  if (n < 2) return NAN;
  double mean = 0, sq = 0;
  for (size_t i = 0; i < n; ++i) mean += (a[i] - b[i]) / n;
  for (size_t i = 0; i < n; ++i) sq += (a[i] - b[i] - mean) * (a[i] - b[i] - mean);
  const double se = std::sqrt(sq / (n - 1) / n);
  if (se > 0) return mean / se;
  return mean > 0 ? INFINITY : mean < 0 ? -INFINITY : 0.0;
}

double SampleSd(const std::vector<double>& v) {
  if (v.size() < 2) return 0;
  double mean = 0, sq = 0;
  for (double x : v) mean += x / static_cast<double>(v.size());
  for (double x : v) sq += (x - mean) * (x - mean);
  return std::sqrt(sq / static_cast<double>(v.size() - 1));
}

int LeadersToRefit(const std::vector<double>& train, int top, double tie, int max_extra) {
  const int n = static_cast<int>(train.size());
  int k = std::min(std::max(top, 0), n);
  if (k == 0) return 0;
  const double last = train[k - 1];
  const int limit = std::min(n, k + std::max(max_extra, 0));
  while (k < limit && train[k] <= last * (1 + tie)) ++k;
  return k;
}

bool LogScaled(double lo, double hi) { return lo > 0 && hi >= 100 * lo; }

bool AtBound(double x, double lo, double hi, double fraction) {
  if (LogScaled(lo, hi)) {
    x = std::log(std::max(x, 1e-300));
    lo = std::log(lo);
    hi = std::log(hi);
  }
  const double margin = fraction * (hi - lo);
  return (lo != 0 && x - lo < margin) || (hi != 0 && hi - x < margin);
}

namespace {

// The first test of the rule `fit` fails against `base`, in words with its figures; empty
// when it passes them all. BeatsBaseline and WhyNotNamed both rest on it.
std::string Shortfall(const FitScore& base, const FitScore& fit, const DecisionRule& rule) {
  if (!fit.ok) return "the fit failed (no valid model)";
  if (fit.at_bound)
    return "a fitted parameter sits at the edge of its range: an implausible value, the mark of "
           "an effect absorbing a mismatch it does not describe";
  const double dbic = fit.bic - base.bic;
  if (!(dbic < -rule.margin))
    return absl::StrFormat("fits the training data no better than the baseline (delta BIC %.1f; "
                           "the rule asks below -%g)",
                           dbic, rule.margin);
  if (!std::isfinite(fit.held)) return "no held-out score";
  const double change = fit.held / base.held - 1;
  if (change >= 0)
    return absl::StrFormat("fits the training data better (delta BIC %.0f) but predicts the "
                           "held-out recordings worse (%+.0f%%): it absorbs the training mismatch",
                           dbic, 100 * change);
  if (!(fit.held < (1 - rule.held_out_gain) * base.held))
    return absl::StrFormat("cuts the held-out error by only %.0f%% (the rule asks %.0f%%)",
                           -100 * change, 100 * rule.held_out_gain);
  const double t = PairedT(base.held_variants, fit.held_variants);
  if (!(t > rule.paired_t))
    return absl::StrFormat("cuts the held-out error by %.0f%% on average, but not consistently "
                           "across the numeric variants (paired t %.2f, the rule asks above %g)",
                           -100 * change, t, rule.paired_t);
  return "";
}

}  // namespace

bool BeatsBaseline(const FitScore& base, const FitScore& fit, const DecisionRule& rule) {
  return Shortfall(base, fit, rule).empty();
}

bool StructureAdmits(const FitScore& base, const FitScore& fit, const DecisionRule& rule) {
  return fit.ok && fit.bic - base.bic < -rule.margin && std::isfinite(fit.held) &&
         fit.held <= base.held + rule.held_floor;
}

namespace {

bool Contains(const FitScore& outer, const FitScore& inner) {
  return std::all_of(inner.effects.begin(), inner.effects.end(), [&](const std::string& e) {
    return std::find(outer.effects.begin(), outer.effects.end(), e) != outer.effects.end();
  });
}

// Whether `fit` misses beating `member` by pair_gain at the finest step (false when the
// rule names no such variant or either fit lacks it).
bool NoGainAtFinestStep(const FitScore& fit, const FitScore& member, const DecisionRule& rule) {
  const int f = rule.finest_step;
  if (f < 0 || f >= static_cast<int>(fit.held_variants.size()) ||
      f >= static_cast<int>(member.held_variants.size()))
    return false;
  return fit.held_variants[f] > (1 - rule.pair_gain) * member.held_variants[f];
}

// A larger fit that contains `member` and does not beat it by the BIC margin and pair_gain
// held out (on the mean and at the finest step): it adds nothing the member lacks (Decide
// drops it; WhyNotNamed says so).
bool AddsNothingTo(const FitScore& fit, const FitScore& member, const DecisionRule& rule) {
  return Contains(fit, member) && (fit.bic > member.bic - rule.margin ||
                                   fit.held > (1 - rule.pair_gain) * member.held ||
                                   NoGainAtFinestStep(fit, member, rule));
}

bool Overlaps(const FitScore& a, const FitScore& b) {
  return std::any_of(a.effects.begin(), a.effects.end(), [&](const std::string& e) {
    return std::find(b.effects.begin(), b.effects.end(), e) != b.effects.end();
  });
}

}  // namespace

Decision Decide(const FitScore& base, const std::vector<FitScore>& fits, const DecisionRule& rule,
                int prefer) {
  std::vector<int> order;
  for (int i = 0; i < static_cast<int>(fits.size()); ++i) order.push_back(i);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return fits[a].effects.size() < fits[b].effects.size();
  });
  std::vector<int> winners;
  for (int i : order) {
    const FitScore& c = fits[i];
    if (!BeatsBaseline(base, c, rule)) continue;
    bool dominated = false;
    for (int w : winners) {
      if (AddsNothingTo(c, fits[w], rule)) dominated = true;
    }
    if (!dominated) winners.push_back(i);
  }
  // Among explanations that all passed, the one that predicts the held-out data best: the
  // training error (and so BIC) of the hopping robot is dominated by one chaotic gait.
  std::stable_sort(winners.begin(), winners.end(),
                   [&](int a, int b) { return fits[a].held < fits[b].held; });
  if (auto p = std::find(winners.begin(), winners.end(), prefer); p != winners.end())
    std::rotate(winners.begin(), p, p + 1);
  // A larger fit that survived its members replaces the best single it contains.
  if (!winners.empty() && fits[winners[0]].effects.size() == 1) {
    for (size_t i = 1; i < winners.size(); ++i) {
      if (fits[winners[i]].effects.size() > 1 && Contains(fits[winners[i]], fits[winners[0]])) {
        std::swap(winners[0], winners[i]);
        break;
      }
    }
  }
  Decision d;
  if (winners.empty()) return d;
  const FitScore& w = fits[winners[0]];
  d.named.push_back(winners[0]);
  for (size_t i = 1; i < winners.size(); ++i) {
    const FitScore& f = fits[winners[i]];
    if (f.effects.size() != 1 || w.effects.size() != 1) continue;
    // Within the BIC margin, or apart by less than the model's own numeric spread on both the
    // training and the held-out recordings: the data cannot tell the two apart.
    const bool within_spread = std::fabs(f.train - w.train) <= rule.train_floor &&
                               std::fabs(f.held - w.held) <= rule.held_floor;
    if (std::fabs(f.bic - w.bic) < rule.margin || within_spread) d.named.push_back(winners[i]);
  }
  if (d.named.size() == 1) {
    // A rival with no effect in common that fits the training data better by the margin and
    // that the held-out data cannot show to be worse (not consistently across the numeric
    // variants, or by no more than the held-out error's own numeric spread): the held-out
    // gain alone does not tell the two apart.
    int rival = -1;
    for (int i = 0; i < static_cast<int>(fits.size()); ++i) {
      const FitScore& f = fits[i];
      if (!f.ok || f.at_bound || Overlaps(f, w) || !(f.bic < w.bic - rule.margin)) continue;
      const bool within_floor = f.held - w.held <= rule.held_floor;
      if (!within_floor && !(PairedT(w.held_variants, f.held_variants) > -rule.paired_t)) continue;
      if (rival < 0 || f.bic < fits[rival].bic) rival = i;
    }
    if (rival >= 0) d.named.push_back(rival);
  }
  d.verdict = d.named.size() > 1 ? "ambiguous" : "found";
  return d;
}

Decision DecideRequired(const FitScore& base, std::vector<FitScore> fits, const DecisionRule& rule,
                        const std::function<std::vector<std::string>(int)>& unneeded,
                        std::vector<int>* set_aside) {
  int prefer = -1, source = -1;
  for (;;) {
    Decision d = Decide(base, fits, rule, prefer);
    if (d.named.empty()) return d;
    const int first = d.named[0];
    const std::vector<std::string> drop = unneeded(first);
    if (drop.empty()) {
      if (first == prefer) d.remainder_of = source;
      return d;
    }
    fits[first].ok = false;  // neither named nor a rival any more
    if (set_aside) set_aside->push_back(first);
    std::vector<std::string> rest;
    for (const auto& e : fits[first].effects)
      if (std::find(drop.begin(), drop.end(), e) == drop.end()) rest.push_back(e);
    std::sort(rest.begin(), rest.end());
    prefer = -1;
    for (int i = 0; i < static_cast<int>(fits.size()) && !rest.empty(); ++i) {
      std::vector<std::string> effects = fits[i].effects;
      std::sort(effects.begin(), effects.end());
      if (effects == rest && BeatsBaseline(base, fits[i], rule)) prefer = i;
    }
    source = first;
  }
}

Decision PreferDetermined(const Decision& d, const std::vector<bool>& undetermined,
                          std::vector<int>* dropped) {
  auto loose = [&](size_t k) { return k < undetermined.size() && undetermined[k]; };
  if (d.named.size() < 2 || loose(0)) return d;
  Decision out = d;
  out.named.clear();
  for (size_t k = 0; k < d.named.size(); ++k) {
    if (k > 0 && loose(k)) {
      if (dropped) dropped->push_back(d.named[k]);
    } else {
      out.named.push_back(d.named[k]);
    }
  }
  out.verdict = out.named.size() > 1 ? "ambiguous" : "found";
  return out;
}

std::string WhyNotNamed(const FitScore& base, const FitScore& fit, const FitScore* winner,
                        const DecisionRule& rule, const std::vector<const FitScore*>& others) {
  if (&fit == winner) return "";
  if (std::string why = Shortfall(base, fit, rule); !why.empty()) return why;
  if (!winner) return "passed every test";
  const std::string larger = absl::StrFormat(
      "(a larger fit must beat its member by the BIC margin and %.0f%% held out%s)",
      100 * rule.pair_gain, rule.finest_step >= 0 ? ", on the mean and at the finest step" : "");
  if (Contains(fit, *winner))
    return "passed every test, but adds nothing the named explanation lacks " + larger;
  for (const FitScore* m : others)  // as Decide: a passing member it does not beat
    if (m && m != &fit && m->effects.size() < fit.effects.size() &&
        BeatsBaseline(base, *m, rule) && AddsNothingTo(fit, *m, rule))
      return absl::StrFormat("passed every test, but adds nothing its member %s lacks %s",
                             absl::StrJoin(m->effects, "+"), larger);
  return absl::StrFormat("passed every test, but the named explanation predicts the held-out "
                         "recordings better (%.3g against %.3g %s)",
                         rule.error_scale * winner->held, rule.error_scale * fit.held,
                         rule.error_unit);
}

}  // namespace gaitforge::diagnosis
