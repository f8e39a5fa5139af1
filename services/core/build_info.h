#pragma once
// The identity of this build, the same string in every binary: what `gaitforge --version`
// prints and what a worker reports as its sim_build (protocol.md, "sim_build").
#include <string>

namespace gaitforge::core {

// "gaitforge-VERSION/ode-ODE_VERSION/COMPILER-COMPILER_VERSION".
std::string BuildId();

}  // namespace gaitforge::core
