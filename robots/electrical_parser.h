#pragma once
// A descriptor's `electrical:` section (descriptor.h, Electrical; docs/robots.md,
// "Electrical").
#include "absl/status/status.h"
#include "robots/descriptor.h"
#include "robots/yaml_fields.h"

namespace gaitforge::robots {

// Reads `node` into d.electrical. Each motor type names servo actuators of d, none twice;
// the numbers are expressions of d's parameters, checked at their nominal values (gear >= 1,
// kt > 0, resistance >= 0, bus_voltage > 0, standby_current >= 0, regen_efficiency in
// [0, 1]). Errors name the source, line, field and what is allowed.
absl::Status ParseElectrical(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d);

}  // namespace gaitforge::robots
