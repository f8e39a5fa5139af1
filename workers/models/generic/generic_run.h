#pragma once
// Running a generic robot from rest step by step under a source of actuator commands: the
// one loop a gait (generic_gait.h) and a playback (a recording's input columns) share.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "robots/descriptor.h"
#include "workers/models/generic/generic_world.h"

namespace gaitforge::generic {

// Each step's actuator commands (descriptor order) into `out`: step i of the run.
using Source = std::function<void(int64_t i, std::vector<double>& out)>;

// Builds the world (`engine`, or the ODE builder when empty) and runs it from rest for
// `steps(world)` steps under the commands `source(world)` gives, calling `each(world, i)`
// before every step and once after the last; false (with the reason and the simulated time
// reached) when it cannot be built or diverges.
bool RunWorld(const robots::RobotDescriptor& d, const ParamValues& v, double timestep_s,
              const WorldBuilder& engine, const std::function<int64_t(const RobotWorld&)>& steps,
              const std::function<void(const RobotWorld&, int64_t)>& each,
              const std::function<Source(const RobotWorld&)>& source, std::string* reason,
              double* simulated_s);

}  // namespace gaitforge::generic
