#pragma once
// "robot.calibration" (services/core/objective_catalog.cc): how far any generic robot's
// model (objective.robot, robot_descriptor) is from recordings of it; fitness = -(mean error
// over the recordings). The comparison is every calibration's (recording_comparison.h):
// the model runs each recording's command (meta.genes) from rest and gives the channels of
// its sensors; the error is paper 003's shift-invariant error of period-averaged signals
// (error = shape, default), pointwise, or stats.
//
// Genes are named (input.gene_names): the robot's parameters and scales, the effects the
// generic builder attaches (effect.*; workers/effects), set in gene order on the nominal
// descriptor, and nuisance.time_offset_s (recording time t is simulated time t + offset).
// Params: settle_cycles 0..20 (the robot's simulation.settle_cycles), max_shift_samples,
// timestep_ms (the robot's simulation.timestep_s), z_weight, min_distance_m. Options: error,
// metric, channels, weights. Metrics: docs/calibration.md, "Metrics".
#include "workers/objectives/objective.h"

namespace gaitforge::generic {

inline constexpr char kRobotCalibrationName[] = "robot.calibration";

class RobotCalibrationObjective : public objectives::Objective {
 public:
  objectives::EvalResult Evaluate(const objectives::EvalInput& in) const override;
};

}  // namespace gaitforge::generic
