#pragma once
// The catalog of objectives: names, parameters with their allowed ranges, and default
// search spaces. The coordinator validates specs against it; workers implement the
// entries (workers/objectives). Documented in docs/objectives.md.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"

namespace gaitforge::core {

struct GeneRange {
  std::string name;
  double lo;
  double hi;
  bool circular = false;  // a phase (robots::Gene::circular)
};

struct ParamInfo {
  std::string name;
  double lo;
  double hi;
  double default_value;
  std::string meaning;  // with units
  bool integer = false;  // only whole numbers
};

struct ObjectiveInfo {
  std::string name;
  std::string summary;
  std::vector<ParamInfo> params;
  // Space used when a spec gives no bounds.
  std::vector<GeneRange> default_space;
  // 0: any number of genes; otherwise exactly this many.
  int required_genes = 0;
  // String options: name -> allowed values (the first is the default).
  std::vector<std::pair<std::string, std::vector<std::string>>> options;
  // Compares with recordings (objective.recordings must name at least one).
  bool needs_recordings = false;
  // A calibration: the genes name calibratable parameters of this built-in robot
  // (robots/<name>/robot.yaml) or one of `nuisance`; empty for other objectives.
  std::string calibrates;
  // A calibration of objective.robot (with uses_robot): the genes name its calibratable
  // parameters and scales, effects the builder attaches to its parts (workers/effects), or
  // one of `nuisance`. True too when `calibrates` names a built-in robot.
  bool calibration = false;
  // Genes that are parameters of the comparison, not of the model.
  std::vector<std::string> nuisance;
  // Robot-agnostic: objective.robot names the robot (a built-in, or a descriptor the spec
  // carries), whose controller's genes are the space (unless `calibration`) and whose
  // parameters `set` may change.
  bool uses_robot = false;
  // The built-in robot whose controller the genes drive, when the objective is bound to
  // one (a dedicated model's gait objective); empty otherwise (uses_robot: objective.robot).
  std::string gait_robot;
  // Takes objective.robust (docs/objectives.md, "Robust evaluation"): param start_phase and
  // option set, which an ensemble's members vary.
  bool robust = false;
};

// The robot whose parameters an objective's `set` option (and a robust ensemble) changes:
// objective.robot for a robot-agnostic objective, else the built-in it is bound to; an
// error when it names none or does not resolve.
absl::StatusOr<std::shared_ptr<const robots::RobotDescriptor>> RobotOfObjective(
    const ObjectiveInfo& info, const std::string& robot, const std::string& descriptor);

// A robot's gene space: its controller's genes (robots/controllers.h).
std::vector<GeneRange> GeneSpaceOf(const robots::RobotDescriptor& robot);

const std::vector<ObjectiveInfo>& ObjectiveCatalog();
// nullptr when unknown.
const ObjectiveInfo* FindObjective(std::string_view name);
// "a, b, c" of every objective name, for error messages.
std::string ObjectiveNames();

}  // namespace gaitforge::core
