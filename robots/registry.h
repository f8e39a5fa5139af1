#pragma once
// The built-in robots: robots/<name>/robot.yaml for every name listed in
// robots/CMakeLists.txt (GAITFORGE_ROBOTS), embedded in the binaries at build time so that a
// coordinator, a worker and the CLI always agree on them, wherever they run.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"

namespace gaitforge::robots {

// The built-in robot of that name, parsed once; nullptr when there is none. A built-in
// descriptor that does not parse is a broken build: the first call throws std::logic_error
// with the parser's message (tests/unit/robots checks that every built-in parses).
const RobotDescriptor* FindRobot(std::string_view name);
// The built-in robot of that name; throws std::out_of_range naming the known ones.
const RobotDescriptor& Robot(std::string_view name);
// Their names, in the order of GAITFORGE_ROBOTS.
std::vector<std::string> RobotNames();
// A built-in descriptor's text as written in its file ("" when unknown).
std::string_view BuiltinText(std::string_view name);
// A file that ships with built-in robot `robot` (robots/<robot>/FILE, a learned model
// *.mlp.json), embedded like its descriptor; "" when there is none.
std::string_view BuiltinFile(std::string_view robot, std::string_view file);

// The robot a study names: `text` parsed when given (a descriptor the spec carries; parsed
// once per distinct text and kept, as its content determines it), else the built-in robot
// `name`. When both are given the descriptor's name must be `name`. Errors name the
// descriptor's line, or the known built-in robots.
absl::StatusOr<std::shared_ptr<const RobotDescriptor>> ResolveRobot(const std::string& name,
                                                                    const std::string& text);

}  // namespace gaitforge::robots
