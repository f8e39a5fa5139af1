#include "workers/worker/registry.h"

#include <stdexcept>

#include "workers/models/caterpillar/calibration_objective.h"
#include "workers/models/caterpillar/caterpillar_objective.h"
#include "workers/models/generic/generic_objective.h"

namespace gaitforge::worker {

absl::StatusOr<objectives::ObjectiveRegistry> WorkerRegistry() {
  objectives::ObjectiveRegistry registry = objectives::DefaultRegistry();
  try {
    caterpillar::RegisterCaterpillar(registry);
    caterpillar::RegisterCaterpillarCalibration(registry);
    generic::RegisterGeneric(registry);
  } catch (const std::exception& e) {
    return absl::FailedPreconditionError(e.what());
  }
  return registry;
}

}  // namespace gaitforge::worker
