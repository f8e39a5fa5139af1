#pragma once
// How a simulation ended: a value, not an exception. A diverged run is ok = false with a
// reason a person can act on ("NaN in lump 3 position at t = 1.204 s").
#include <string>

namespace gaitforge::sim {

struct SimOutcome {
  bool ok = true;
  std::string reason;  // empty when ok

  static SimOutcome Ok() { return {}; }
  static SimOutcome Failed(std::string why) { return {false, std::move(why)}; }
};

}  // namespace gaitforge::sim
