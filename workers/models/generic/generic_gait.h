#pragma once
// One gait of a generic robot (model: generic): from rest, settle_cycles gait periods, then
// measured_cycles more; fitness is the forward (+x) travel of the robot's centre of mass
// over the measured cycles, per cycle (m). The controller kind (robots/controllers.h) turns
// the genes into each actuator's command over time.
#include <string>
#include <vector>

#include "robots/descriptor.h"
#include "workers/models/generic/generic_world.h"

namespace gaitforge::generic {

struct GaitOptions {
  int settle_cycles = -1;    // < 0: the robot's simulation.settle_cycles
  int measured_cycles = -1;  // < 0: the robot's simulation.measured_cycles
  double timestep_s = 0;     // <= 0: the robot's simulation.timestep_s
};

struct GaitResult {
  bool valid = false;
  std::string reason;               // why not valid
  double distance_per_cycle_m = 0;  // the fitness
  double simulated_s = 0;
};

// Commands (rad) of each actuator, in descriptor order, at time t for these genes; an
// error when the controller kind cannot drive this robot's actuators.
absl::StatusOr<std::vector<double>> Commands(const robots::RobotDescriptor& d,
                                             const std::vector<double>& genes, double t);

// Never throws for a diverging model: that is valid = false with the reason.
GaitResult EvaluateGait(const robots::RobotDescriptor& d, const ParamValues& values,
                        const std::vector<double>& genes, const GaitOptions& options = {});

}  // namespace gaitforge::generic
