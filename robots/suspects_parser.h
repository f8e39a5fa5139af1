#pragma once
// The "suspects" section of a descriptor: model errors the robot's authors suspect (a
// paper's own list of what its simulation may get wrong), each a set of calibratable
// parameters or scales with the range a fit may search (docs/robots.md, "Suspects").
#include "absl/status/status.h"
#include "robots/descriptor.h"
#include "robots/yaml_fields.h"

namespace gaitforge::robots {

// Appends the suspects under `node` to d.suspects. Needs d's parameters and scales: every
// fitted name must be calibratable, its range inside the parameter's and holding its value.
absl::Status ParseSuspects(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d);

// Appends the `ruled_out` mapping (EFFECT_ID: WHY, a non-empty reason each) to d.ruled_out.
// The ids are checked against the effect catalog where it is known (a diagnosis's
// validation), not here: robots/ does not depend on the catalog.
absl::Status ParseRuledOut(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d);

}  // namespace gaitforge::robots
