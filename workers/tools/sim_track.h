#pragma once
// gaitforge-sim track: paper 004's tracking of a path by a generic robot's kinematic PID,
// with or without a model's feed-forward (workers/models/generic/generic_tracking.h).
#include <string>

#include "absl/status/statusor.h"
#include "workers/tools/generic_sim.h"

namespace gaitforge::simtool {

struct TrackArgs {
  std::string path;                 // a path recording (CSV with sidecar)
  std::string feedforward = "none";  // none | model
  std::string model_set;            // the model's overrides NAME=VALUE,... (feedforward model)
  std::string model_learned;        // an MLP file setting the model's parameters (adaptive)
  int ff_iterations = 20;           // model runs that learn the feed-forward
  bool feedback = true;             // false: feed-forward alone
  std::string out;                  // CSV of every tick, "" for none
};

// Tracks a.path with run.robot under run.overrides (the plant); JSON of the errors and, with
// a feed-forward, how well the model itself follows under it. Errors: a bad argument
// (InvalidArgument), a plant or model that cannot run the path (Aborted).
absl::StatusOr<std::string> GenericTrack(const GenericRun& run, const TrackArgs& a);

}  // namespace gaitforge::simtool
