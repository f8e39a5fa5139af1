// The gap finder (docs/diagnosis.md): a study of calibration studies that locates a mismatch
// between a model and recordings, names the physics the model left out, fits it and shows
// the held-out error fall, or says that nothing in the catalog explains it. Robot-agnostic:
// the robot's calibration objective, gene space and channels come from its descriptor.
//   1. baseline: calibrate the base model (its uncertain parameters and the time offset;
//      marker offsets are profiled out), every fit weighting the training recordings by
//      their noise floors (weighting: floor, FloorWeights) or equally;
//   2. locate: slice the baseline's residuals on the training and the held-out recordings
//      against the model's own spread under the numeric variants (locate.h);
//   3. screen every candidate effect (workers/effects) with a short fit, all at once;
//   4. refit the leading candidates fully, and pairs of them;
//   5. decide (decision.h) by BIC on the training error and by the held-out error over an
//      ensemble of numerically irrelevant variants, each named effect required and pinned
//      by the data (range.h); read "none" against the located spread;
//   6. report: diagnosis.json, its figures and the corrected model (report.h).
#pragma once

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "gaitforge/v1/diagnosis.pb.h"
#include "services/diagnosis/studies.h"

namespace gaitforge::diagnosis {

struct Inputs {
  std::vector<std::string> train, held;              // recordings, by content hash
  std::vector<std::string> train_files, held_files;  // their local copies (calibration-eval)
  std::string dir;  // where evaluations, figures, the report and the corrected model go
};

// Runs the diagnosis d (validated, defaults applied) on the studies' coordinator; writes
// dir/diagnosis.json and returns it (one JSON object, docs/diagnosis.md "The report").
// Fails when the baseline cannot be fitted, an evaluation of the uncalibrated model fails,
// a recording does not parse, or the reporter asks to stop.
absl::StatusOr<std::string> Diagnose(const v1::DiagnosisSpec& d, const Inputs& in,
                                     Studies& studies, const Reporter& r);

}  // namespace gaitforge::diagnosis
