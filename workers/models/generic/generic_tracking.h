#pragma once
// Paper 004's tracking on any generic robot with a `tracking:` section (robots/descriptor.h,
// Tracking; docs/robots.md, "Tracking"): a kinematic PID steers a marker along a path, with
// or without a model's feed-forward. The feed-forward of a model is learned on the model
// itself by iterative learning control (LearnFeedForward): the forces that take the
// model's marker along the path, found by running it, so any robot the generic builder
// makes, and any model of it (constant parameters, effects, learned ones), has one.
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"
#include "services/recording/recording.h"
#include "workers/models/generic/generic_world.h"

namespace gaitforge::generic {

// Where the tracked marker should be: its steered axes' positions (m) at path times (s,
// from the path's start).
struct Path {
  std::vector<double> t;
  std::vector<std::vector<double>> axes;  // one column per Tracking::axes entry
};

// The path a recording gives for d's tracked marker (its `<marker>.<axis>` columns, any
// command kind; a "path" recording is one). An error names the recording's missing column.
absl::StatusOr<Path> PathOf(const robots::RobotDescriptor& d, const recording::Recording& rec,
                            const std::string& name);

// Every actuator's force (N) at each control tick from rest, the lead-in included.
struct FeedForward {
  std::vector<std::vector<double>> forces;  // [tick][actuator]
  int iterations = 0;                       // model runs that learned it
  double residual_rms_m = 0, residual_max_m = 0;  // the model's own error under it, on the path
};

struct TrackingOptions {
  double timestep_s = 0;   // <= 0: the robot's simulation.timestep_s
  bool feedback = true;    // false: the feed-forward alone (open loop)
  WorldBuilder engine;     // empty: ODE
};

struct TrackingResult {
  bool valid = false;
  std::string reason;
  std::vector<double> t;                                // ticks, s from the path's start (< 0: lead-in)
  std::vector<std::vector<double>> reference, position;  // [axis][tick], m
  std::vector<std::vector<double>> command;             // [actuator][tick], N
  // Over the path's ticks (t >= 0): the marker's distance from the reference on the steered
  // axes, its largest and RMS value (m), and ISTE = integral of t e^2 dt (m^2 s^2).
  double max_error_m = 0, rms_error_m = 0, iste = 0;
};

// Runs d (values v) from rest: during tracking.lead_s the reference eases (half a cosine)
// from the marker's rest position to the path's start, then follows the path; every
// 1 / tracking.rate_hz the PID's correction (when o.feedback) plus ff's forces (when given)
// are commanded and held. Invalid with the reason when the robot cannot track, the rate is
// not a whole number of timesteps, or the simulation diverges.
TrackingResult Track(const robots::RobotDescriptor& d, const ParamValues& v, const Path& path,
                     const FeedForward* ff, const TrackingOptions& o);

// The feed-forward of the model (d, values `model`) for `path`: open-loop runs of the model,
// each correcting the forces by a gain times the rod-length errors it left (smoothed over
// 0.1 s, one tick ahead), the gain raised after a better run and halved after a worse one
// (the best forces kept), for `iterations` runs.
absl::StatusOr<FeedForward> LearnFeedForward(const robots::RobotDescriptor& d,
                                             const ParamValues& model, const Path& path,
                                             int iterations, const TrackingOptions& o);

}  // namespace gaitforge::generic
