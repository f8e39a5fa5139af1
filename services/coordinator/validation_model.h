#pragma once
// The model a validation study predicts with (StudySpec.validate.from_calibration;
// docs/objectives.md, "Validation"): the study's own, or a later calibration's. Calibrate,
// evolve, record the best gaits, calibrate again on all recordings: the second
// calibration's model ranks the first study's gaits without a second evolution.
#include <string>

#include "absl/status/status.h"
#include "gaitforge/v1/study.pb.h"
#include "services/coordinator/from_calibration.h"
#include "storage/study_store.h"

namespace gaitforge::coordinator {

// `first`'s NAME=VALUE items, then those of `second` whose names `first` does not set.
std::string MergeSets(const std::string& first, const std::string& second);

// *study's objective re-based on calibration study `id`: resolved as
// objective.from_calibration resolves a new study's (ResolveFromCalibration) with the
// study's objective name, robot, params and robust settings; then the study's own option
// `set` items and ensemble parameters that the calibration does not set are kept after the
// calibration's. The study's timestep stays. Refused (InvalidArgument, naming
// validate.from_calibration): an ensemble with joint samples of its own (they belong to
// its model), and what ResolveFromCalibration refuses, with its code.
absl::Status RebaseOnCalibration(storage::StudyStore& store, const SpreadFn& spread_after,
                                 const std::string& id, v1::StudySpec* study);

}  // namespace gaitforge::coordinator
