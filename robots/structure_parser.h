#pragma once
// The structure sections of a descriptor (docs/robots.md, "Structure"): bodies, joints,
// actuators and ground, which the generic model builds. Names must refer to declared
// bodies, joints and parameters; the controller's actuators must be the declared ones.
#include "absl/status/status.h"
#include "robots/descriptor.h"
#include "robots/yaml_fields.h"

namespace gaitforge::robots {

// [x, y, z] of numbers, parameter names or expressions of them.
absl::Status ReadVec3(const YamlFields& f, const YAML::Node& node, const std::string& path,
                      const RobotDescriptor& d, Vec3Expr& out);

// A number, a parameter's name or a linear expression of them (expr.h); its names must be
// parameters of d.
absl::Status ReadExprField(const YamlFields& f, const YAML::Node& node, const std::string& path,
                           const RobotDescriptor& d, Expr& out);

// Reads whichever of root's bodies, joints, actuators and ground are present into d.
absl::Status ParseStructure(const YamlFields& f, const YAML::Node& root, RobotDescriptor& d);

}  // namespace gaitforge::robots
