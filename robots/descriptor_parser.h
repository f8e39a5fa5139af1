#pragma once
// Reads a robot descriptor (format gaitforge.robot.v1, docs/robots.md) from YAML or JSON
// text. Strict: every field is checked against its allowed values, unknown and repeated
// keys are errors, and each error names file:line:column, the field and the allowed range.
#include <string>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"

namespace gaitforge::robots {

inline constexpr char kDescriptorFormat[] = "gaitforge.robot.v1";

// `source` names the text in errors (a path, or "caterpillar (built in)").
absl::StatusOr<RobotDescriptor> ParseDescriptor(const std::string& text,
                                                const std::string& source);
absl::StatusOr<RobotDescriptor> LoadDescriptor(const std::string& path);

}  // namespace gaitforge::robots
