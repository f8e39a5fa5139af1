#pragma once
// gaitforge-sim for a robot on the generic builder (model: generic; docs/robots.md): its
// sensors' channels over one gait as a recording (trajectory), and the robot.calibration
// objective against recordings (calibration-eval), the same model build as the workers.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"
#include "services/recording/recording.h"
#include "workers/learned/mlp.h"
#include "workers/models/generic/generic_world.h"

namespace gaitforge::simtool {

struct GenericRun {
  const robots::RobotDescriptor* robot = nullptr;
  std::string robot_path;     // the descriptor file ("" for a built-in robot)
  std::string robot_text;     // its text (what a study carries)
  std::vector<std::pair<std::string, double>> overrides;  // --set, in order
  std::string learned;  // --learned: an MLP file setting parameters from the state (or "")
  double rate_hz = 100;
  int settle_cycles = 2, cycles = 10;
  // trajectory: the engine that builds the robot ("ode", the studies' build, or "mujoco",
  // an independent build: workers/models/mujoco/).
  std::string engine = "ode";
};

// An MLP file (docs/learned-models.md), read and checked.
absl::StatusOr<learned::Mlp> ReadMlp(const std::string& path);

// The descriptor's values with run.overrides applied (not the nuisance ones) and run.learned
// attached; the error names the bad --set or file.
absl::StatusOr<generic::ParamValues> RunValues(const GenericRun& run);

// A recording CSV and its sidecar (path + ".json"), parsed for run.robot.
absl::StatusOr<recording::Recording> ReadRecording(const std::string& path, const GenericRun& run);

// The robot's channels over the measured cycles of `genes` after the settle cycles from
// rest (times counted from rest), written as a recording CSV at `out` with its sidecar. The error names a bad gene count, a bad --set
// or a diverging simulation.
absl::Status GenericTrajectory(const GenericRun& run, const std::vector<double>& genes,
                               const std::string& out);

// The robot driven from rest by the input columns of `inputs` (a CSV of t and every
// actuator's input channel, robots::Actuator::InputChannel; checked as a recording is) until
// its last time, its channels and the inputs at rate_hz written as a playback recording at
// `out` with its sidecar (docs/recording-format.md).
absl::Status GenericPlayback(const GenericRun& run, const std::string& inputs,
                             const std::string& out);

// For each recording (comma-separated CSV paths with sidecars): robot.calibration's error and
// metrics with the overrides as genes, and (with out_dir) the simulated channels of the
// recording's gait as out_dir/sim-<i>.csv. Returns JSON, as CalibrationEval does.
absl::StatusOr<std::string> GenericCalibrationEval(const GenericRun& run,
                                                   const std::string& recordings,
                                                   const std::map<std::string, std::string>& options,
                                                   const std::map<std::string, double>& params,
                                                   const std::string& out_dir);

}  // namespace gaitforge::simtool
