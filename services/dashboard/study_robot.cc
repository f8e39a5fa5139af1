#include "services/dashboard/study_robot.h"

#include "absl/strings/str_cat.h"
#include "robots/controllers.h"
#include "robots/registry.h"
#include "services/core/objective_catalog.h"
#include "services/dashboard/json_text.h"

namespace gaitforge::dashboard {
namespace {

std::string ControllerJson(const robots::Controller& c) {
  std::vector<std::string> actuators, genes;
  for (const auto& a : c.actuators) actuators.push_back(JsonString(a));
  for (const auto& g : c.genes)
    genes.push_back(JsonObject(
        {{"name", JsonString(g.name)}, {"lo", JsonNumber(g.lo)}, {"hi", JsonNumber(g.hi)}}));
  const robots::ControllerKind* kind = robots::FindControllerKind(c.kind);
  return JsonObject({{"kind", JsonString(c.kind)},
                     {"doc", JsonString(kind ? kind->doc : "")},
                     {"actuators", JsonArray(actuators)},
                     {"genes", JsonArray(genes)}});
}

}  // namespace

std::string StudyRobotJson(const v1::StudySpec& spec) {
  const v1::ObjectiveSpec& o = spec.objective();
  const core::ObjectiveInfo* info = core::FindObjective(o.name());
  std::string note;
  if (info == nullptr) {
    note = absl::StrCat("unknown objective '", o.name(), "'");
  } else if (info->calibration) {
    // A calibration's genes are the robot's parameters, not its controller's: shown by
    // name within their bounds.
    auto robot = info->uses_robot ? robots::ResolveRobot(o.robot(), o.robot_descriptor())
                                  : robots::ResolveRobot(info->calibrates, "");
    return JsonObject(
        {{"robot", JsonString(robot.ok() ? (*robot)->name : "")},
         {"controller", "null"},
         {"note", JsonString(robot.ok() ? "a calibration: its genes are the robot's parameters, "
                                          "shown as positions within their bounds"
                                        : std::string(robot.status().message()))}});
  } else if (info->uses_robot || !info->gait_robot.empty()) {
    auto robot = info->uses_robot ? robots::ResolveRobot(o.robot(), o.robot_descriptor())
                                  : robots::ResolveRobot(info->gait_robot, "");
    if (robot.ok())
      return JsonObject({{"robot", JsonString((*robot)->name)},
                         {"controller", ControllerJson((*robot)->controller)}});
    note = std::string(robot.status().message());
  } else {
    note = absl::StrCat("objective ", o.name(), " drives no robot's controller: its genes are "
                        "shown as positions within their bounds");
  }
  return JsonObject(
      {{"robot", JsonString("")}, {"controller", "null"}, {"note", JsonString(note)}});
}

}  // namespace gaitforge::dashboard
