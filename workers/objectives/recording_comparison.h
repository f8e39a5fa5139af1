#pragma once
// Comparing a model with recordings, for every calibration objective ("robot.calibration" and
// a robot's own name for it): a model simulates a recording's command from rest and gives its
// channels (markers "m1.x", joint angles "hinge.angle", ...) sampled regularly; this file
// chooses the compared channels, runs the simulation long enough, and computes the error
// (calibration_error.h: paper 003's phase-shift-invariant error of period-averaged signals,
// pointwise, or stats) and the metrics. It names no robot: the model side is a Simulator.
//
// Channels: by default every channel of the recording that the simulation gives; option
// `channels` names some. A channel ending in .x, .y or .z is a position on that axis (its
// profiled offset joins offset_x/y/z; the .x ones give the distance per cycle of their mean).
// Errors pool the compared channels in their own units (m, rad).
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "services/recording/recording.h"
#include "workers/objectives/calibration_error.h"
#include "workers/objectives/objective.h"

namespace gaitforge::calibration {

inline constexpr char kTimeOffsetGene[] = "nuisance.time_offset_s";

enum class Mode { kShape, kPointwise, kStats, kAcceleration };

struct CompareSettings {
  Mode mode = Mode::kShape;
  Metric metric = Metric::kRmse;
  std::vector<std::string> channels;  // option channels; empty: every channel both have
  int settle_cycles = 2;
  int max_shift = 10;
  double timestep_s = 0;
  double z_weight = 1;
  double min_distance_m = 1e-3;
  double window_s = 0;  // error = acceleration: compare the first window_s of each recording (0: all)
  std::vector<double> weights;  // per recording; empty: equal
};

// The objective's params (settle_cycles, max_shift_samples, timestep_ms, z_weight,
// min_distance_m, window_s) and options (error, metric, channels, weights), each checked against its
// range; `known_channels` are the channels the robot can give (option channels must be
// among them). `timestep_s` stays 0 unless the param timestep_ms is given.
absl::StatusOr<CompareSettings> ParseCompareSettings(const objectives::EvalInput& in,
                                                     int default_settle_cycles,
                                                     const std::vector<std::string>& known_channels,
                                                     const std::string& robot);

// Channels of a simulation sampled at regular times from rest.
struct Trajectory {
  std::vector<double> t;
  std::vector<std::string> channels;
  Signals columns;  // parallel to channels
  int Index(std::string_view name) const;  // -1 if absent
};

struct SimRun {
  bool valid = false;
  std::string reason;  // why not valid
  double simulated_s = 0;
  Trajectory trajectory;
};

// Runs the recording's command from rest for at least duration_s (a gait: whole periods),
// sampling every channel at rate_hz (a whole number of timesteps per sample).
using Simulator = std::function<SimRun(double duration_s, double rate_hz)>;

// What one recording gives.
struct Comparison {
  double error = 0;
  int shift = 0;
  double time_shift_s = 0;
  std::array<double, 3> offset_sum{};  // per axis, over the compared channels
  std::array<int, 3> offset_count{};
  bool has_distance = false;
  double real_distance = 0, sim_distance = 0;
  double simulated_s = 0;
  double period_s = 0;  // the gait period compared over
};

// Compares one recording of a command with period `period_s` (recording time t is
// simulated time t + offset_s); period_s = 0 for a command that does not repeat (a
// playback), which error = shape and stats cannot compare and settle_cycles does not
// apply to. The simulator runs once, with s.timestep_s steps.
//
// error = acceleration (paper 004): the error is RelativeAccelerationError
// (acceleration_error.h) between the Savitzky-Golay accelerations of the recorded and the
// simulated channels on the recording's regular grid, channels .x/.y/.z of one name making
// one point's vector, over the recording's first window_s (all of it when 0; the first and
// last 4 samples have no centred filter window), minimised over time shifts of up to
// max_shift_samples intervals; 1 - error is the paper's F.
absl::StatusOr<Comparison> CompareRecording(const recording::Recording& rec, double period_s,
                                            double offset_s, const CompareSettings& s,
                                            const Simulator& simulate);

// Every recording of `in` compared by `compare`, weighted by s.weights: fitness = -(weighted
// mean error), metrics error, error_<i>, best_shift_<i>, time_shift_s_<i>, period_s_<i>, distances and
// their ratio, offset_x/y/z, simulated_s. A failed comparison makes the result invalid with
// "recording <i>: <why>".
objectives::EvalResult CompareAll(
    const objectives::EvalInput& in, const CompareSettings& s, const std::string& objective,
    const std::function<absl::StatusOr<Comparison>(const recording::Recording&)>& compare);

}  // namespace gaitforge::calibration
