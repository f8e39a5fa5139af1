#include "robots/controllers.h"

namespace gaitforge::robots {
namespace {

// Paper 000's gait: actuator j is ON while the phase (t mod T)/T lies in [a_j, d_j),
// wrapping round when d_j < a_j. Genes: every a_j, then every d_j, in [0, 1), then T (s).
std::vector<Gene> PhaseOnOffGenes(const Controller& c) {
  std::vector<Gene> genes;
  for (const char* prefix : {"a_", "d_"})
    for (const auto& a : c.actuators) genes.push_back({prefix + a, 0, 1});
  genes.push_back({"T", c.period_lo, c.period_hi});
  return genes;
}

}  // namespace

const std::vector<ControllerKind>& ControllerKinds() {
  static const std::vector<ControllerKind> kinds = {
      {"phase_onoff",
       "on/off actuators switched by the phase of a periodic gait: per actuator an "
       "activation and a deactivation phase in [0, 1), then the period T (paper 000)",
       &PhaseOnOffGenes},
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
