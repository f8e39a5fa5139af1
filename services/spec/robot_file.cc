#include "services/spec/robot_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/match.h"
#include "robots/descriptor_parser.h"

namespace gaitforge::spec {

bool LooksLikeRobotPath(const std::string& robot) {
  return robot.find('/') != std::string::npos || absl::EndsWith(robot, ".yaml") ||
         absl::EndsWith(robot, ".json");
}

absl::Status EmbedRobotFile(LoadedSpec& loaded) {
  auto* o = loaded.spec.mutable_objective();
  if (!o->robot_descriptor().empty() || o->robot().empty()) return absl::OkStatus();
  std::filesystem::path path(o->robot());
  if (path.is_relative()) path = std::filesystem::path(loaded.source).parent_path() / path;
  std::error_code ec;
  // A built-in robot's name, unless a file or folder of that name stands beside the spec.
  if (!LooksLikeRobotPath(o->robot()) && !std::filesystem::exists(path, ec))
    return absl::OkStatus();
  std::string where = loaded.source;
  if (auto it = loaded.marks.find("objective.robot"); it != loaded.marks.end())
    where = absl::StrCat(loaded.source, ":", it->second.line, ":", it->second.column);
  if (std::filesystem::is_directory(path, ec)) path /= "robot.yaml";
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return absl::NotFoundError(absl::StrCat(where, ": field 'objective.robot': cannot open '",
                                            path.string(), "'"));
  std::stringstream text;
  text << in.rdbuf();
  auto d = robots::ParseDescriptor(text.str(), path.string());
  if (!d.ok())
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": field 'objective.robot': ", d.status().message()));
  o->set_robot(d->name);
  o->set_robot_descriptor(text.str());
  return absl::OkStatus();
}

}  // namespace gaitforge::spec
