#pragma once
// A validation study (StudySpec.validate; docs/objectives.md, "Validation"): when it is
// created, the coordinator makes it a sweep over the gaits of the robust study it names,
// each over a fresh ensemble (services/spec/validation_spec.h). The stored spec holds the
// result, so the validation stays reproducible when the study is gone.
#include "absl/status/status.h"
#include "gaitforge/v1/study.pb.h"
#include "services/coordinator/from_calibration.h"
#include "storage/study_store.h"

namespace gaitforge::coordinator {

// No-op without spec->validate, or for a spec that is a validation study already (an
// objective, a sweep and validate's gaits: a stored one submitted again). Otherwise
// replaces *spec by the validation study of
// validate.study_id: its gaits (validate.gaits, or the first validate.top valid gaits of
// its latest hall of fame), its objective and bounds (with validate.from_calibration, its
// objective re-based on that calibration: RebaseOnCalibration), the fresh ensemble. Refused: an
// unknown study (NotFound), a spec that also sets an objective, bounds, constraints,
// population or generations (they come from the study), top with gaits, no valid gait,
// and ValidationSpec's refusals.
absl::Status ResolveValidation(storage::StudyStore& store, const SpreadFn& spread_after,
                               v1::StudySpec* spec);

}  // namespace gaitforge::coordinator
