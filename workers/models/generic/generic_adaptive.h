#pragma once
// Paper 004's adaptive model on any generic robot: parameters estimated recording by
// recording (each a playback from rest: the robot held by its inputs in one state), then an
// MLP (workers/learned) trained from each recording's state to its parameters; the model
// that sets them from its state every step (ParamValues::SetLearned) is the adaptive one.
// Beside it, the constant model: one set of parameters fitted to all recordings at once.
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"
#include "services/recording/recording.h"
#include "workers/learned/mlp.h"
#include "workers/models/generic/generic_world.h"

namespace gaitforge::generic {

// The robot's marker channels in both the recording and its playback: their RMS distance
// over the recording's samples from `from_fraction` of its duration on (m; 0: all of
// them); infinite when the playback is invalid.
double PlaybackError(const robots::RobotDescriptor& d, const ParamValues& v,
                     const recording::Recording& rec, double from_fraction = 0);

struct ParameterFit {
  std::vector<double> values;  // parallel to the names fitted
  double error_m = 0;          // PlaybackError at them (summed over recordings: the mean)
  int evaluations = 0;
};

// Nelder-Mead over `names` (each within its parameter's range, from the base values) on
// the mean PlaybackError over `recs` (from from_fraction of each), at most max_evaluations
// playbacks of each, the recordings played on `threads` threads (the same result for any).
absl::StatusOr<ParameterFit> FitParameters(const robots::RobotDescriptor& d, const ParamValues& base,
                                           const std::vector<const recording::Recording*>& recs,
                                           const std::vector<std::string>& names,
                                           int max_evaluations, double from_fraction = 0,
                                           int threads = 1);

// A recording's state: each input channel's mean over the recording's second half (a
// ".rate" input: the mean rate of its channel there), the MLP's inputs for its parameters.
absl::StatusOr<std::vector<double>> RecordingState(const recording::Recording& rec,
                                                   const std::vector<std::string>& inputs);

struct AdaptiveModel {
  learned::Mlp mlp;
  learned::TrainReport report;
  std::vector<ParameterFit> per_recording;  // parallel to the recordings
  ParameterFit constant;                    // all recordings at once
};

// Fits `names` on all of every recording together (the constant model), then on each
// recording's second half (the state it holds), from the constant model's values and held
// near them where the recording does not show a parameter (an axis it does not bend), and
// trains the MLP from `inputs`
// (channels, ".rate" for rates) to the per-recording values. The per-recording fits run on
// `threads` threads; the result does not depend on how many.
absl::StatusOr<AdaptiveModel> LearnAdaptiveModel(const robots::RobotDescriptor& d,
                                                 const ParamValues& base,
                                                 const std::vector<const recording::Recording*>& recs,
                                                 const std::vector<std::string>& inputs,
                                                 const std::vector<std::string>& names,
                                                 int max_evaluations,
                                                 const learned::TrainOptions& train,
                                                 int threads = 1);

}  // namespace gaitforge::generic
