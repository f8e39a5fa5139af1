#include "robots/registry.h"

#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "robots/descriptor_parser.h"

namespace gaitforge::robots {

// builtin_robots.cc (generated).
const std::vector<std::pair<std::string_view, std::string_view>>& BuiltinRobotTexts();
const std::vector<std::pair<std::string_view, std::string_view>>& BuiltinRobotFiles();

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

std::string_view BuiltinFile(std::string_view robot, std::string_view file) {
  const std::string key = absl::StrCat(std::string(robot), "/", std::string(file));
  for (const auto& [name, text] : BuiltinRobotFiles())
    if (name == key) return text;
  return {};
}

std::vector<std::string> RobotNames() {
  std::vector<std::string> names;
  for (const auto& [name, text] : BuiltinRobotTexts()) names.emplace_back(name);
  return names;
}

absl::StatusOr<std::shared_ptr<const RobotDescriptor>> ResolveRobot(const std::string& name,
                                                                    const std::string& text) {
  if (text.empty()) {
    const RobotDescriptor* r = FindRobot(name);
    if (r == nullptr)
      return absl::NotFoundError(absl::StrCat("no built-in robot '", name, "' (known: ",
                                              absl::StrJoin(RobotNames(), ", "),
                                              "); or give a descriptor file's path"));
    // Built-ins live for the process: a non-owning pointer.
    return std::shared_ptr<const RobotDescriptor>(std::shared_ptr<void>(), r);
  }
  static std::mutex mu;
  static auto* parsed = new std::map<std::string, std::shared_ptr<const RobotDescriptor>>;
  std::shared_ptr<const RobotDescriptor> d;
  {
    std::lock_guard<std::mutex> lock(mu);
    if (auto it = parsed->find(text); it != parsed->end()) d = it->second;
  }
  if (d == nullptr) {
    auto p = ParseDescriptor(text, name.empty() ? "robot descriptor" : name + " (descriptor)");
    if (!p.ok()) return p.status();
    d = std::make_shared<const RobotDescriptor>(std::move(*p));
    std::lock_guard<std::mutex> lock(mu);
    if (parsed->size() > 64) parsed->clear();  // a bound, not an LRU: studies name few robots
    parsed->emplace(text, d);
  }
  if (!name.empty() && d->name != name)
    return absl::InvalidArgumentError(absl::StrCat("the descriptor's name is '", d->name,
                                                   "', not '", name, "'"));
  return d;
}

std::string_view BuiltinText(std::string_view name) {
  for (const auto& [n, text] : BuiltinRobotTexts())
    if (n == name) return text;
  return {};
}

}  // namespace gaitforge::robots
