#pragma once
// A recording's input columns driving a generic robot (a recording whose command kind is
// "playback", docs/recording-format.md): paper 004's arm is run with its measured rod
// forces. Each actuator's command at simulated time s is its column (robots::Actuator::
// InputChannel) at recording time s - offset_s - d, d the actuator delay
// (effect.actuator_delay_s): linear between samples, the first or last value held outside.
#include "robots/descriptor.h"
#include "services/recording/recording.h"
#include "workers/models/generic/robot_world.h"
#include "workers/objectives/recording_comparison.h"

namespace gaitforge::generic {

// The robot's channels sampled at rate_hz (a whole number of timesteps per sample; timestep_s
// <= 0: the robot's simulation.timestep_s) from rest for duration_s, times counted from rest.
// Invalid with the reason when the recording lacks an actuator's column or the model
// diverges.
calibration::SimRun SimulatePlayback(const robots::RobotDescriptor& d, const ParamValues& values,
                                     const recording::Recording& rec, double offset_s,
                                     double duration_s, double rate_hz, double timestep_s = 0,
                                     const WorldBuilder& engine = {});

}  // namespace gaitforge::generic
