#pragma once
// "robot.distance" (services/core/objective_catalog.cc): forward travel per gait cycle of
// any generic robot, the robot named by the job (EvalInput::robot, robot_descriptor).
// Params: cycles, settle_cycles, timestep_ms (defaults: the robot's simulation.*).
// Option set: overrides NAME=VALUE,... of the robot's parameters, each in its range.
// Metrics: distance_per_cycle, simulated_s.
#include "workers/objectives/objective.h"

namespace gaitforge::generic {

inline constexpr char kRobotDistanceName[] = "robot.distance";

class RobotDistanceObjective : public objectives::Objective {
 public:
  objectives::EvalResult Evaluate(const objectives::EvalInput& in) const override;
};

void RegisterGeneric(objectives::ObjectiveRegistry& registry);

}  // namespace gaitforge::generic
