#pragma once
// A spec's objective.robot may be a descriptor file's path (or a robot folder holding
// robot.yaml), relative to the spec file: the spec then carries the descriptor's text
// (objective.robot_descriptor) and the robot's name, so coordinator and workers need no
// file, and the study keeps what it was run with (docs/robots.md, "Robots in studies").
#include "absl/status/status.h"
#include "services/spec/spec_loader.h"

namespace gaitforge::spec {

// True when `robot` reads as a path rather than a built-in robot's name.
bool LooksLikeRobotPath(const std::string& robot);

// Reads and checks the descriptor objective.robot names, when it names a file. A missing
// or bad file is an error naming the spec's line and the descriptor's own file:line.
absl::Status EmbedRobotFile(LoadedSpec& loaded);

// The same for any spec: `robot` (the field `field`, written at `where`: "spec.yaml:3:8")
// names a file relative to the spec file `source`; then `robot` becomes the robot's name and
// `descriptor` the file's text.
absl::Status EmbedRobotFile(const std::string& source, const std::string& where,
                            const std::string& field, std::string* robot,
                            std::string* descriptor);

}  // namespace gaitforge::spec
