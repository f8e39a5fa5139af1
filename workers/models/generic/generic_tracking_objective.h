#pragma once
// "robot.tracking" (services/core/objective_catalog.cc): paper 004's tracking as a study.
// Any generic robot with a `tracking:` section (objective.robot) follows each recording (a
// path: its tracked marker's channels; workers/models/generic/generic_tracking.h) from rest
// with its PID; fitness = -(mean over the paths of ISTE, the largest or the RMS error:
// option fitness). Genes are the robot's parameters named in bounds (the gains
// tracking.kp, tracking.ki, tracking.kd as paper 004 tuned them by ISTE, or any other),
// set on the robot that tracks: the descriptor with option `set` (the plant). Option
// feedforward: none, or model: the feed-forward of the descriptor with option model_set,
// learned once per worker, path and model (param ff_iterations runs) and kept. Metrics:
// max_error_m, rms_error_m, iste (means over the paths), model_rms_error_m.
#include "workers/objectives/objective.h"

namespace gaitforge::generic {

inline constexpr char kRobotTrackingName[] = "robot.tracking";

class RobotTrackingObjective : public objectives::Objective {
 public:
  objectives::EvalResult Evaluate(const objectives::EvalInput& in) const override;
};

}  // namespace gaitforge::generic
