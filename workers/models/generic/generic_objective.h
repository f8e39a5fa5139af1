#pragma once
// "robot.distance" (services/core/objective_catalog.cc): forward travel per gait cycle of
// any generic robot, the robot named by the job (EvalInput::robot, robot_descriptor).
// Params: cycles, settle_cycles, timestep_ms (defaults: the robot's simulation.*).
// Option set: overrides NAME=VALUE,... of the robot's parameters, each in its range.
// Metrics: distance_per_cycle (or travel), simulated_s, max_tilt_rad,
// torque_limited_fraction, servo_energy_j, cost_of_transport, max_body_pitch,
// airborne_fraction; with pistons max_stroke and actuator_energy (docs/objectives.md).
#include <memory>
#include <string>

#include "workers/objectives/objective.h"

namespace gaitforge::generic {

inline constexpr char kRobotDistanceName[] = "robot.distance";

class RobotDistanceObjective : public objectives::Objective {
 public:
  objectives::EvalResult Evaluate(const objectives::EvalInput& in) const override;
};

void RegisterGeneric(objectives::ObjectiveRegistry& registry);

// A built-in robot's own name for a robot-agnostic objective (its descriptor's
// `objectives:`): `name` evaluates as `objective` (robot.distance or robot.calibration)
// with the job's robot set to `robot`.
void RegisterRobotObjective(objectives::ObjectiveRegistry& registry, const std::string& name,
                            const std::string& objective, const std::string& robot);

}  // namespace gaitforge::generic
