#include "robots/controllers.h"

#include <cmath>

#include "robots/leg_gait.h"
#include "robots/leg_stance.h"

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

// Four coupled phase oscillators (paper 003's CPG; Kuramoto form): for the actuators FL, FR,
// HL, HR (in that order) with target phases 0, lr, fh, fh + lr (cycles),
//   d phi_i / dt = 2 pi f + w sum_{j != i} sin(phi_j - phi_i - 2 pi (target_j - target_i)),
// from phi = 2 pi (0, 0.1, 0.2, 0.3) (a spread like no pattern, so the coupling has to lock
// it; all equal phases would be an equilibrium of a walk); hip_i = off + amp sin(phi_i),
// front or hind amp and off. lr = 0 is a bound,
// 0.5 a walk on diagonals (a trot). Genes: f, amp_front, amp_hind, off_front, off_hind, lr,
// fh, w (1/s).
std::vector<Gene> CpgGenes(const Controller& c) {
  const auto& f = c.ranges.at("frequency_hz");
  const auto& amp = c.ranges.at("amplitude_rad");
  const auto& off = c.ranges.at("offset_rad");
  const auto& w = c.ranges.at("coupling_per_s");
  return {{"f", f[0], f[1]},          {"amp_front", amp[0], amp[1]}, {"amp_hind", amp[0], amp[1]},
          {"off_front", off[0], off[1]}, {"off_hind", off[0], off[1]}, {"lr", 0, 1, true},
          {"fh", 0, 1, true},         {"w", w[0], w[1]}};
}

std::vector<double> CpgTargets(const std::vector<double>& g) {
  return {0, g[5], g[6], g[6] + g[5]};
}

std::vector<double> CpgInitial(const Controller&, const std::vector<double>&) {
  return {0.0, 0.2 * M_PI, 0.4 * M_PI, 0.6 * M_PI};
}

std::vector<double> CpgRates(const std::vector<double>& g, const std::vector<double>& phi) {
  const std::vector<double> target = CpgTargets(g);
  std::vector<double> rate(4, 2 * M_PI * g[0]);
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (j != i) rate[i] += g[7] * std::sin(phi[j] - phi[i] - 2 * M_PI * (target[j] - target[i]));
  return rate;
}

// One classical Runge-Kutta step.
void CpgAdvance(const Controller&, const std::vector<double>& g, double dt,
                std::vector<double>& phi) {
  auto shifted = [&](const std::vector<double>& k, double by) {
    std::vector<double> out = phi;
    for (int i = 0; i < 4; ++i) out[i] += by * k[i];
    return out;
  };
  const auto k1 = CpgRates(g, phi);
  const auto k2 = CpgRates(g, shifted(k1, dt / 2));
  const auto k3 = CpgRates(g, shifted(k2, dt / 2));
  const auto k4 = CpgRates(g, shifted(k3, dt));
  for (int i = 0; i < 4; ++i) phi[i] += dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
}

std::vector<double> CpgCommands(const Controller&, const std::vector<double>& g,
                                const std::vector<double>& phi) {
  std::vector<double> out(4);
  for (int i = 0; i < 4; ++i)
    out[i] = (i < 2 ? g[3] : g[4]) + (i < 2 ? g[1] : g[2]) * std::sin(phi[i]);
  return out;
}

std::vector<double> CpgAt(const Controller& c, const std::vector<double>& genes, double t) {
  return ControllerRun(c, genes).At(t);
}

// hold: no genes; every actuator held at 0 (a servo's straight set-point).
std::vector<Gene> HoldGenes(const Controller&) { return {}; }
double HoldPeriod(const std::vector<double>&) { return 1.0; }
std::vector<double> HoldCommands(const Controller& c, const std::vector<double>&, double) {
  return std::vector<double>(c.actuators.size(), 0.0);
}

}  // namespace

ControllerRun::ControllerRun(const Controller& c, std::vector<double> genes)
    : c_(c), kind_(*FindControllerKind(c.kind)), genes_(std::move(genes)) {
  if (kind_.initial_state) state_ = kind_.initial_state(c_, genes_);
}

std::vector<double> ControllerRun::At(double t, const BodyState* base) {
  if (kind_.feedback && base) return kind_.feedback(c_, genes_, t, *base);
  if (!kind_.advance) return kind_.commands(c_, genes_, t);
  const long target = static_cast<long>(std::floor(t / kStep + 1e-9));
  for (; steps_ < target; ++steps_) kind_.advance(c_, genes_, kStep, state_);
  return kind_.state_commands(c_, genes_, state_);
}

const std::vector<ControllerKind>& ControllerKinds() {
  static const std::vector<ControllerKind> kinds = {
      {"phase_onoff",
       "on/off actuators switched by the phase of a periodic gait: per actuator an "
       "activation and a deactivation phase in [0, 1), then the period T (paper 000)",
       {"period_s"},
       &PhaseOnOffGenes,
       &PhaseOnOffPeriod,
       &PhaseOnOffCommands,
       false,
       0,
       nullptr,
       nullptr,
       nullptr,
       0.05,  // a pneumatic valve's fastest useful cycle; the lumped model's own limits
       10},
      {"hold",
       "no gait: every actuator holds its zero set-point, no genes (a passive structure, "
       "or one whose motion comes from its start or from gravity); a cycle is 1 s",
       {},
       &HoldGenes,
       &HoldPeriod,
       &HoldCommands},
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
      {"cpg",
       "four coupled phase oscillators (Kuramoto) for hips FL, FR, HL, HR: genes f, amp_front, "
       "amp_hind, off_front, off_hind, lr (left-right phase: 0 bound, 0.5 walk), fh "
       "(front-hind phase), w (coupling, 1/s) (paper 003)",
       {"frequency_hz", "amplitude_rad", "offset_rad", "coupling_per_s"},
       &CpgGenes,
       &SinePeriod,
       &CpgAt,
       true,
       4,
       &CpgInitial,
       &CpgAdvance,
       &CpgCommands},
      {"leg_gait",
       "a quadruped's gait scheduler: per foot a straight stance stroke backwards and a "
       "cycloid swing, through each leg's two-link inverse kinematics; genes T, stance, lift, "
       "speed, height, load (the weight's share on the stance feet, "
       "fed forward as torques), lr (left-right phase: 0.5 trot, 0 paper 002's slide), fh "
       "(front-rear phase); 12 actuators, legs FR, FL, RR, RL x (hip, thigh, calf) (paper 002)",
       {"period_s", "stance_ratio", "lift_m", "speed_m_per_s", "height_m", "load_share"},
       &LegGaitGenes,
       &LegGaitPeriod,
       &LegGaitCommands,
       true,
       12,
       nullptr,
       nullptr,
       nullptr,
       0.05,
       1e300,
       {"thigh_m", "calf_m", "thigh_stand_rad", "calf_stand_rad", "mass_kg", "front_hip_x_m",
        "rear_hip_x_m", "hip_y_m", "hip_z_m", "hip_offset_m"},
       true,
       &LegGaitFeedback,
       &LegGaitCheck},
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
