#pragma once
// gaitforge-sim learn-parameters: paper 004's adaptive model for a generic robot from
// playback recordings (workers/models/generic/generic_adaptive.h), written as an MLP file
// (docs/learned-models.md), with the constant model beside it on held-out recordings.
#include <string>

#include "absl/status/statusor.h"
#include "workers/learned/mlp.h"
#include "workers/tools/generic_sim.h"

namespace gaitforge::simtool {

struct LearnArgs {
  std::string recordings, held_out;  // comma-separated playback recordings
  std::string params;                // the parameters learned, comma separated
  std::string features;              // the MLP's inputs: channels, ".rate" for rates
  std::string out;                   // the MLP file to write
  int evaluations = 150;             // Nelder-Mead playbacks per fit
  int epochs = 5000;
  int hidden = 5;                    // units of the one hidden layer (paper 004: 5)
  int threads = 1;                   // fits at once
};

// JSON: each recording's fitted parameters and error, the constant fit, the MLP's training
// report, and on the held-out recordings the constant and the adaptive model's errors.
absl::StatusOr<std::string> GenericLearn(const GenericRun& run, const LearnArgs& a);

}  // namespace gaitforge::simtool
