#include "clients/cli/diagnosis_decision.h"

#include <algorithm>
#include <cmath>

namespace gaitforge::cli {

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

bool AtBound(double x, double lo, double hi, double fraction) {
  if (lo > 0 && hi >= 100 * lo) {
    x = std::log(std::max(x, 1e-300));
    lo = std::log(lo);
    hi = std::log(hi);
  }
  const double margin = fraction * (hi - lo);
  return (lo != 0 && x - lo < margin) || (hi != 0 && hi - x < margin);
}

bool BeatsBaseline(const FitScore& base, const FitScore& fit, const DecisionRule& rule) {
  return fit.ok && !fit.at_bound && fit.bic - base.bic < -rule.margin && std::isfinite(fit.held) &&
         fit.held < (1 - rule.held_out_gain) * base.held &&
         PairedT(base.held_variants, fit.held_variants) > rule.paired_t;
}

namespace {

bool Contains(const FitScore& outer, const FitScore& inner) {
  return std::all_of(inner.effects.begin(), inner.effects.end(), [&](const std::string& e) {
    return std::find(outer.effects.begin(), outer.effects.end(), e) != outer.effects.end();
  });
}

bool Overlaps(const FitScore& a, const FitScore& b) {
  return std::any_of(a.effects.begin(), a.effects.end(), [&](const std::string& e) {
    return std::find(b.effects.begin(), b.effects.end(), e) != b.effects.end();
  });
}

}  // namespace

Decision Decide(const FitScore& base, const std::vector<FitScore>& fits, const DecisionRule& rule) {
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
      if (Contains(c, fits[w]) &&
          (c.bic > fits[w].bic - rule.margin || c.held > (1 - rule.pair_gain) * fits[w].held))
        dominated = true;
    }
    if (!dominated) winners.push_back(i);
  }
  // Among explanations that all passed, the one that predicts the held-out data best: the
  // training error (and so BIC) of the hopping robot is dominated by one chaotic gait.
  std::stable_sort(winners.begin(), winners.end(),
                   [&](int a, int b) { return fits[a].held < fits[b].held; });
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
  for (size_t i = 1; i < winners.size(); ++i)
    if (std::fabs(fits[winners[i]].bic - w.bic) < rule.margin &&
        fits[winners[i]].effects.size() == 1 && w.effects.size() == 1)
      d.named.push_back(winners[i]);
  if (d.named.size() == 1) {
    // A rival with no effect in common that fits the training data better by the margin and
    // that the held-out data cannot show to be worse: the held-out gain alone does not tell
    // the two apart.
    int rival = -1;
    for (int i = 0; i < static_cast<int>(fits.size()); ++i) {
      const FitScore& f = fits[i];
      if (!f.ok || f.at_bound || Overlaps(f, w) || !(f.bic < w.bic - rule.margin)) continue;
      if (!(PairedT(w.held_variants, f.held_variants) > -rule.paired_t)) continue;
      if (rival < 0 || f.bic < fits[rival].bic) rival = i;
    }
    if (rival >= 0) d.named.push_back(rival);
  }
  d.verdict = d.named.size() > 1 ? "ambiguous" : "found";
  return d;
}

}  // namespace gaitforge::cli
