#pragma once
// The objectives this worker binary implements: the analytic family and every robot model.
#include "absl/status/statusor.h"
#include "workers/objectives/objective.h"

namespace gaitforge::worker {

// Fails (with the file, line and field) when a model's parameter file is missing or invalid.
absl::StatusOr<objectives::ObjectiveRegistry> WorkerRegistry();

}  // namespace gaitforge::worker
