#include "workers/worker/registry.h"

#include <stdexcept>

#include "robots/registry.h"
#include "workers/models/generic/generic_calibration.h"
#include "workers/models/generic/generic_objective.h"

namespace gaitforge::worker {

absl::StatusOr<objectives::ObjectiveRegistry> WorkerRegistry() {
  objectives::ObjectiveRegistry registry = objectives::DefaultRegistry();
  try {
    generic::RegisterGeneric(registry);
    // Built-in robots' own names for the robot objectives bound to them (their descriptors'
    // `objectives:`; stored studies and the papers' examples use them).
    for (const std::string& name : robots::RobotNames()) {
      const robots::RobotDescriptor& r = robots::Robot(name);
      if (!r.distance_objective.empty())
        generic::RegisterRobotObjective(registry, r.distance_objective, generic::kRobotDistanceName, name);
      if (!r.calibration_objective.empty())
        generic::RegisterRobotObjective(registry, r.calibration_objective,
                                        generic::kRobotCalibrationName, name);
    }
  } catch (const std::exception& e) {
    return absl::FailedPreconditionError(e.what());
  }
  return registry;
}

}  // namespace gaitforge::worker
