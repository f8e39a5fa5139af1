#pragma once
// A gait study that starts from a diagnosis (objective.from_diagnosis; docs/objectives.md,
// "Robust evaluation"): the diagnosis's corrected model becomes the study's objective, and
// with objective.robust the named effect's fitted ranges become ensemble parameters, so
// gaits are evolved for the robot as the data describe it, over what the data leave open.
#include "absl/status/status.h"
#include "gaitforge/v1/study.pb.h"
#include "storage/study_store.h"

namespace gaitforge::coordinator {

// Fills spec->objective from diagnosis objective.from_diagnosis (no-op when unset): its
// name and robot (when the spec gives none; another name is an error), option set (the
// corrected model's values, then the spec's own items, which win), and for a robust study
// one parameter per fitted effect parameter over its range (the fit's range; value +- 2 sd
// on an open side), unless the spec already lists it. NotFound for an unknown diagnosis,
// FailedPrecondition for one not completed or that named no explanation.
absl::Status ResolveFromDiagnosis(storage::StudyStore& store, v1::StudySpec* spec);

}  // namespace gaitforge::coordinator
