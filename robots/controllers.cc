#include "robots/controllers.h"

#include <cmath>

namespace gaitforge::robots {
namespace {

// Paper 000's gait: actuator j is ON while the phase (t mod T)/T lies in [a_j, d_j),
// wrapping round when d_j < a_j. Genes: every a_j, then every d_j, in [0, 1), then T (s).
std::vector<Gene> PhaseOnOffGenes(const Controller& c) {
  std::vector<Gene> genes;
  for (const char* prefix : {"a_", "d_"})
    for (const auto& a : c.actuators) genes.push_back({prefix + a, 0, 1, true});
  const auto& t = c.ranges.at("period_s");
  genes.push_back({"T", t[0], t[1]});
  return genes;
}

double PhaseOnOffPeriod(const std::vector<double>& genes) { return genes.back(); }

double Wrap01(double x) {
  const double w = x - std::floor(x);
  return w >= 1.0 ? 0.0 : w;
}

std::vector<double> PhaseOnOffCommands(const Controller&, const std::vector<double>& genes,
                                       double t) {
  const size_t n = (genes.size() - 1) / 2;
  const double period = genes.back();
  const double phase = std::fmod(t, period) / period;  // in [0, 1) for t >= 0
  std::vector<double> out(n);
  for (size_t j = 0; j < n; ++j) {
    const double a = Wrap01(genes[j]), d = Wrap01(genes[n + j]);
    out[j] = (a <= d ? (phase >= a && phase < d) : (phase >= a || phase < d)) ? 1.0 : 0.0;
  }
  return out;
}

// A sine per actuator about an offset, all at one frequency f (paper 001): actuator j's
// target is off_j + amp_j sin(2 pi (f t + phase_j)). Genes: f (Hz), then per actuator
// amp_j (rad), off_j (rad) and phase_j (cycles, [0, 1)).
std::vector<Gene> SineGenes(const Controller& c) {
  const auto& f = c.ranges.at("frequency_hz");
  const auto& amp = c.ranges.at("amplitude_rad");
  const auto& off = c.ranges.at("offset_rad");
  std::vector<Gene> genes = {{"f", f[0], f[1]}};
  for (const auto& a : c.actuators) {
    genes.push_back({"amp_" + a, amp[0], amp[1]});
    genes.push_back({"off_" + a, off[0], off[1]});
    genes.push_back({"phase_" + a, 0, 1, true});
  }
  return genes;
}

double SinePeriod(const std::vector<double>& genes) { return 1.0 / genes.front(); }

std::vector<double> SineCommands(const Controller&, const std::vector<double>& genes, double t) {
  const size_t n = (genes.size() - 1) / 3;
  const double f = genes[0];
  std::vector<double> out(n);
  for (size_t k = 0; k < n; ++k) {
    const double amp = genes[1 + 3 * k], off = genes[2 + 3 * k], phase = genes[3 + 3 * k];
    out[k] = off + amp * std::sin(2 * M_PI * (f * t + phase));
  }
  return out;
}

// One sine shared by every actuator, each a fixed fraction of a cycle ahead of the one
// before it (paper 001's two hips: one frequency, stroke and neutral angle, a small phase
// offset against pitching). Genes f (Hz), amp (rad), off (rad), lag (cycles): actuator k's
// target is off + amp sin(2 pi (f t + k lag)).
std::vector<Gene> SineSyncGenes(const Controller& c) {
  const auto& f = c.ranges.at("frequency_hz");
  const auto& amp = c.ranges.at("amplitude_rad");
  const auto& off = c.ranges.at("offset_rad");
  const auto& lag = c.ranges.at("lag_cycles");
  return {{"f", f[0], f[1]}, {"amp", amp[0], amp[1]}, {"off", off[0], off[1]},
          {"lag", lag[0], lag[1]}};
}

std::vector<double> SineSyncCommands(const Controller& c, const std::vector<double>& genes,
                                     double t) {
  std::vector<double> out(c.actuators.size());
  for (size_t k = 0; k < out.size(); ++k)
    out[k] = genes[2] + genes[1] * std::sin(2 * M_PI * (genes[0] * t + static_cast<double>(k) * genes[3]));
  return out;
}

}  // namespace

const std::vector<ControllerKind>& ControllerKinds() {
  static const std::vector<ControllerKind> kinds = {
      {"phase_onoff",
       "on/off actuators switched by the phase of a periodic gait: per actuator an "
       "activation and a deactivation phase in [0, 1), then the period T (paper 000)",
       {"period_s"},
       &PhaseOnOffGenes,
       &PhaseOnOffPeriod,
       &PhaseOnOffCommands,
       false},
      {"sine",
       "a sine per actuator about an offset at one shared frequency: genes f, then per "
       "actuator amp_, off_, phase_ (paper 001)",
       {"frequency_hz", "amplitude_rad", "offset_rad"},
       &SineGenes,
       &SinePeriod,
       &SineCommands},
      {"sine_sync",
       "one sine for every actuator, each lag cycles ahead of the one before: genes f, amp, "
       "off, lag (paper 001's hips)",
       {"frequency_hz", "amplitude_rad", "offset_rad", "lag_cycles"},
       &SineSyncGenes,
       &SinePeriod,
       &SineSyncCommands},
  };
  return kinds;
}

const ControllerKind* FindControllerKind(std::string_view name) {
  for (const auto& k : ControllerKinds())
    if (k.name == name) return &k;
  return nullptr;
}

std::vector<std::string> ControllerKindNames() {
  std::vector<std::string> names;
  for (const auto& k : ControllerKinds()) names.push_back(k.name);
  return names;
}

}  // namespace gaitforge::robots
