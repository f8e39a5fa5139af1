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

absl::Status EmbedRobotFile(const std::string& source, const std::string& where,
                            const std::string& field, std::string* robot,
                            std::string* descriptor) {
  if (!descriptor->empty() || robot->empty()) return absl::OkStatus();
  std::filesystem::path path(*robot);
  if (path.is_relative()) path = std::filesystem::path(source).parent_path() / path;
  std::error_code ec;
  // A built-in robot's name, unless a file or folder of that name stands beside the spec.
  if (!LooksLikeRobotPath(*robot) && !std::filesystem::exists(path, ec)) return absl::OkStatus();
  if (std::filesystem::is_directory(path, ec)) path /= "robot.yaml";
  std::ifstream in(path, std::ios::binary);
  if (!in)
    return absl::NotFoundError(
        absl::StrCat(where, ": field '", field, "': cannot open '", path.string(), "'"));
  std::stringstream text;
  text << in.rdbuf();
  auto d = robots::ParseDescriptor(text.str(), path.string());
  if (!d.ok())
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": field '", field, "': ", d.status().message()));
  *robot = d->name;
  *descriptor = text.str();
  return absl::OkStatus();
}

absl::Status EmbedRobotFile(LoadedSpec& loaded) {
  auto* o = loaded.spec.mutable_objective();
  std::string where = loaded.source;
  if (auto it = loaded.marks.find("objective.robot"); it != loaded.marks.end())
    where = absl::StrCat(loaded.source, ":", it->second.line, ":", it->second.column);
  std::string robot = o->robot(), descriptor = o->robot_descriptor();
  if (auto s = EmbedRobotFile(loaded.source, where, "objective.robot", &robot, &descriptor);
      !s.ok())
    return s;
  o->set_robot(robot);
  o->set_robot_descriptor(descriptor);
  return absl::OkStatus();
}

}  // namespace gaitforge::spec
