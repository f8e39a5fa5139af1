#pragma once
// The "relations" section of a descriptor: linear relations between parameters that must
// hold, e.g. "lumps.spacing_m + actuators.front_attach_x_m - actuators.rear_attach_x_m <=
// actuators.max_length_m". Each entry is that text, or {check: TEXT, why: WHY}.
#include "absl/status/status.h"
#include "robots/descriptor.h"
#include "robots/yaml_fields.h"

namespace gaitforge::robots {

// Appends the relations under `node` to d.relations; every name must be a parameter of d.
absl::Status ParseRelations(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d);

}  // namespace gaitforge::robots
