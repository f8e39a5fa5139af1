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

std::string WaveShape::Name() const {
  return absl::StrCat(front_first ? "head-first" : "tail-first",
                      interleaved ? " interleaved " : " rows ",
                      static_cast<int>(std::lround(100 * duty)), "%");
}

const std::vector<WaveShape>& WaveFamily() {
  static const std::vector<WaveShape> family = [] {
    std::vector<WaveShape> f;
    for (double duty : {0.5, 1.0 / 3.0})
      for (bool interleaved : {false, true})
        for (bool front_first : {false, true}) f.push_back({front_first, interleaved, duty});
    return f;
  }();
  return family;
}

std::vector<double> WaveGenes(double period_s, const WaveShape& shape) {
  std::vector<double> g(kGenes);
  for (int j = 0; j < 3; ++j) {
    const int k = shape.front_first ? 2 - j : j;  // position of pair j in the wave
    const double top_on = shape.interleaved ? 2 * k / 6.0 : k / 6.0;
    const double bottom_on = shape.interleaved ? (2 * k + 1) / 6.0 : k / 6.0 + 0.5;
    g[j] = Wrap01(top_on);                                   // a_Tj
    g[kActuators + j] = Wrap01(top_on + shape.duty);         // d_Tj
    g[3 + j] = Wrap01(bottom_on);                            // a_Bj
    g[kActuators + 3 + j] = Wrap01(bottom_on + shape.duty);  // d_Bj
  }
  g[12] = period_s;
  return g;
}

std::vector<double> TravellingWaveGenes(double period_s) { return WaveGenes(period_s, {}); }

}  // namespace gaitforge::caterpillar
