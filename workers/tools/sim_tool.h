#pragma once
// One-shot simulations of a robot for reports and exports (gaitforge-sim): the same model
// and build as the workers, run on this machine, no coordinator involved.
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/objectives/recording_comparison.h"

namespace gaitforge::simtool {

// Writes channels as a recording CSV (docs/recording-format.md: t, then the channels) and its
// JSON sidecar (robot, parameter file, the gait command, overrides).
// `playback`: the command is a playback (the input columns are among tr's), not a gait.
absl::Status WriteChannels(const calibration::Trajectory& tr, const std::string& csv_path,
                           const std::string& robot, const std::string& params_path,
                           const std::vector<double>& genes, const std::string& note,
                           const std::vector<std::pair<std::string, double>>& overrides = {},
                           bool playback = false);

// Runs fn(i) for i in [0, n) on `threads` threads (each initialised for ODE).
void ParallelFor(int n, int threads, const std::function<void(int)>& fn);

// `s` escaped for a JSON string.
std::string JsonEscape(const std::string& s);

struct SweepPoint {
  double scale = 0;    // period multiplier (period sweep) or 0 (wave)
  double period_s = 0;
  std::string shape;   // wave: WaveShape::Name(); else empty
  generic::GaitResult eval;
};

// Evaluates `genes` with the gait period multiplied by each scale (the same pattern): the
// controller's gene T scaled, or its frequency f divided. An error when it has neither.
absl::StatusOr<std::vector<SweepPoint>> PeriodSweep(const robots::RobotDescriptor& d,
                                                    const generic::ParamValues& values,
                                                    const std::vector<double>& genes,
                                                    const std::vector<double>& scales,
                                                    const generic::GaitOptions& options,
                                                    int threads);

// Paper 000's travelling waves (robots/onoff_waves.h) at each period, for a phase_onoff
// robot whose actuators form two rows; an error for another.
absl::StatusOr<std::vector<SweepPoint>> WaveSweep(const robots::RobotDescriptor& d,
                                                  const generic::ParamValues& values,
                                                  const std::vector<double>& periods,
                                                  const generic::GaitOptions& options,
                                                  int threads);

std::string SweepJson(const std::vector<SweepPoint>& points);

// "name=value,name=value" in order.
absl::StatusOr<std::vector<std::pair<std::string, double>>> ParseOverrides(const std::string& text);

// "k=v;k=v" (values may hold commas, e.g. channels=m1.x,m1.z).
absl::StatusOr<std::map<std::string, std::string>> ParseOptions(const std::string& text);

// "a,b,n": n values evenly spaced from a to b (geometric when `geometric`).
absl::StatusOr<std::vector<double>> ParseRange(const std::string& text, bool geometric);
// `count` numbers (the robot's controller's genes), comma or space separated.
absl::StatusOr<std::vector<double>> ParseGenes(const std::string& text, size_t count);

}  // namespace gaitforge::simtool
