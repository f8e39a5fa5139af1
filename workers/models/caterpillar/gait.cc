#include "workers/models/caterpillar/gait.h"

#include <cmath>

#include "absl/strings/str_cat.h"

namespace gaitforge::caterpillar {
namespace {

double Wrap01(double x) {
  double w = x - std::floor(x);
  return w >= 1.0 ? 0.0 : w;
}

}  // namespace

absl::StatusOr<Gait> Gait::FromGenes(const std::vector<double>& genes) {
  if (genes.size() != kGenes) {
    return absl::InvalidArgumentError(
        absl::StrCat("the caterpillar gait needs 13 genes, got ", genes.size()));
  }
  for (size_t i = 0; i < genes.size(); ++i) {
    if (!std::isfinite(genes[i])) {
      return absl::InvalidArgumentError(absl::StrCat("gene ", i, " is not finite"));
    }
  }
  const double period = genes[12];
  if (period < kMinPeriodS || period > kMaxPeriodS) {
    return absl::InvalidArgumentError(absl::StrCat("gait period T = ", period,
                                                   " s is outside [", kMinPeriodS, ", ",
                                                   kMaxPeriodS, "] s"));
  }
  Gait g;
  for (int j = 0; j < kActuators; ++j) {
    g.on_[j] = Wrap01(genes[j]);
    g.off_[j] = Wrap01(genes[kActuators + j]);
  }
  g.period_s_ = period;
  return g;
}

uint32_t Gait::OnMask(double t) const {
  const double phase = std::fmod(t, period_s_) / period_s_;  // in [0, 1) for t >= 0
  uint32_t mask = 0;
  for (int j = 0; j < kActuators; ++j) {
    const double a = on_[j], d = off_[j];
    const bool on = a <= d ? (phase >= a && phase < d) : (phase >= a || phase < d);
    if (on) mask |= 1u << j;
  }
  return mask;
}

}  // namespace gaitforge::caterpillar
