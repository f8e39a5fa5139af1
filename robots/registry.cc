#include "robots/registry.h"

#include <memory>
#include <stdexcept>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "robots/descriptor_parser.h"

namespace gaitforge::robots {

// builtin_robots.cc (generated).
const std::vector<std::pair<std::string_view, std::string_view>>& BuiltinRobotTexts();

namespace {

const std::vector<std::unique_ptr<RobotDescriptor>>& Builtins() {
  static const auto* robots = [] {
    auto* v = new std::vector<std::unique_ptr<RobotDescriptor>>;
    for (const auto& [name, text] : BuiltinRobotTexts()) {
      const std::string source = absl::StrCat("robots/", std::string(name), "/robot.yaml");
      auto d = ParseDescriptor(std::string(text), source);
      if (!d.ok()) throw std::logic_error(std::string(d.status().message()));
      if (d->name != name)
        throw std::logic_error(absl::StrCat(source, ": name must be '", std::string(name), "'"));
      v->push_back(std::make_unique<RobotDescriptor>(std::move(*d)));
    }
    return v;
  }();
  return *robots;
}

}  // namespace

const RobotDescriptor* FindRobot(std::string_view name) {
  for (const auto& r : Builtins())
    if (r->name == name) return r.get();
  return nullptr;
}

const RobotDescriptor& Robot(std::string_view name) {
  if (const RobotDescriptor* r = FindRobot(name)) return *r;
  throw std::out_of_range(absl::StrCat("no built-in robot '", std::string(name), "' (known: ",
                                       absl::StrJoin(RobotNames(), ", "), ")"));
}

std::vector<std::string> RobotNames() {
  std::vector<std::string> names;
  for (const auto& [name, text] : BuiltinRobotTexts()) names.emplace_back(name);
  return names;
}

std::string_view BuiltinText(std::string_view name) {
  for (const auto& [n, text] : BuiltinRobotTexts())
    if (n == name) return text;
  return {};
}

}  // namespace gaitforge::robots
