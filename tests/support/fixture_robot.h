#pragma once
// The robots that exist only as test fixtures (tests/fixtures/robots/NAME/robot.yaml), read
// once per test binary.
#include <map>
#include <stdexcept>
#include <string>

#include "robots/descriptor_parser.h"

namespace gaitforge::testing {

// Throws with the parser's message when the fixture does not parse.
inline const robots::RobotDescriptor& FixtureRobot(const std::string& name) {
  static std::map<std::string, robots::RobotDescriptor> loaded;
  auto it = loaded.find(name);
  if (it != loaded.end()) return it->second;
  auto r = robots::LoadDescriptor(std::string(GAITFORGE_SOURCE_DIR) + "/tests/fixtures/robots/" +
                                  name + "/robot.yaml");
  if (!r.ok()) throw std::runtime_error(std::string(r.status().message()));
  return loaded.emplace(name, *std::move(r)).first->second;
}

}  // namespace gaitforge::testing
