#pragma once
// Numerically irrelevant variants of a robot's model: changes of its numerics (timestep,
// contact softness) that a sound result must not depend on. The gap finder scores every
// held-out error over them (docs/diagnosis.md) and a robust evaluation may average over
// them (docs/objectives.md, "Robust evaluation").
#include <string>
#include <vector>

#include "robots/descriptor.h"

namespace gaitforge::robots {

// "" (the model as it is), then NAME=VALUE overrides: three timesteps and two contact
// softnesses, those whose parameter robot d has.
std::vector<std::string> StandardNumerics(const RobotDescriptor& d);

}  // namespace gaitforge::robots
