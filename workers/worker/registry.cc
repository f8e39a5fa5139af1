#include "workers/worker/registry.h"

#include <stdexcept>

#include "workers/models/generic/generic_calibration.h"
#include "workers/models/generic/generic_objective.h"

namespace gaitforge::worker {

absl::StatusOr<objectives::ObjectiveRegistry> WorkerRegistry() {
  objectives::ObjectiveRegistry registry = objectives::DefaultRegistry();
  try {
    generic::RegisterGeneric(registry);
    // The caterpillar paper's objective names (stored studies and examples use them).
    generic::RegisterRobotObjective(registry, "caterpillar.distance", generic::kRobotDistanceName,
                                    "caterpillar");
    generic::RegisterRobotObjective(registry, "caterpillar.calibration",
                                    generic::kRobotCalibrationName, "caterpillar");
  } catch (const std::exception& e) {
    return absl::FailedPreconditionError(e.what());
  }
  return registry;
}

}  // namespace gaitforge::worker
