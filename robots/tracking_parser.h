#pragma once
// A descriptor's `tracking:` section (descriptor.h, Tracking; docs/robots.md, "Tracking").
#include "absl/status/status.h"
#include "robots/descriptor.h"
#include "robots/yaml_fields.h"

namespace gaitforge::robots {

// Reads `node` into d.tracking. Its marker must be one of d's marker sensors carrying the
// axes named, and d must have a tendon actuator to steer; the numbers are expressions of
// d's parameters. Errors name the source, line, field and what is allowed.
absl::Status ParseTracking(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d);

}  // namespace gaitforge::robots
