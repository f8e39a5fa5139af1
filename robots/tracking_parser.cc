// A descriptor's `tracking:` section (tracking_parser.h).
#include "robots/tracking_parser.h"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "robots/structure_parser.h"

namespace gaitforge::robots {
namespace {

using Status = absl::Status;

// The marker sensor group that holds marker `name`, or nullptr.
const Sensor* MarkerSensor(const RobotDescriptor& d, const std::string& name) {
  for (const Sensor& s : d.sensors)
    if (s.kind == "marker" && std::find(s.names.begin(), s.names.end(), name) != s.names.end())
      return &s;
  return nullptr;
}

std::vector<std::string> MarkerNames(const RobotDescriptor& d) {
  std::vector<std::string> names;
  for (const Sensor& s : d.sensors)
    if (s.kind == "marker") names.insert(names.end(), s.names.begin(), s.names.end());
  return names;
}

Status ReadAxes(const YamlFields& f, const YAML::Node& node, const Sensor& sensor,
                Tracking& t) {
  auto axes = f.StringList(node, "tracking.axes");
  if (!axes.ok()) return axes.status();
  if (axes->empty()) return f.Error(node, "tracking.axes", "name at least one of x, y, z");
  for (const std::string& a : *axes) {
    if (std::find(sensor.axes.begin(), sensor.axes.end(), a) == sensor.axes.end())
      return f.Error(node, "tracking.axes",
                     absl::StrCat("'", a, "' is not an axis the marker records (",
                                  absl::StrJoin(sensor.axes, ", "), ")"));
    const int axis = a == "x" ? 0 : a == "y" ? 1 : 2;
    if (std::find(t.axes.begin(), t.axes.end(), axis) != t.axes.end())
      return f.Error(node, "tracking.axes", absl::StrCat("'", a, "' is named twice"));
    t.axes.push_back(axis);
  }
  return absl::OkStatus();
}

}  // namespace

Status ParseTracking(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d) {
  const std::vector<std::string> keys = {"marker", "axes", "lever", "kp", "ki", "kd", "rate_hz",
                                         "lead_s"};
  if (!node.IsMap()) return f.Error(node, "tracking", "expected a mapping");
  if (Status s = f.CheckMap(node, "tracking", keys); !s.ok()) return s;
  Tracking t;
  t.mark = f.MarkOf(node);
  auto marker = f.String(node["marker"], "tracking.marker");
  if (!marker.ok()) return marker.status();
  const Sensor* sensor = MarkerSensor(d, *marker);
  if (sensor == nullptr)
    return f.Error(node["marker"], "tracking.marker",
                   absl::StrCat("no marker named '", *marker, "' (markers: ",
                                absl::StrJoin(MarkerNames(d), ", "), ")"));
  t.marker = *marker;
  if (Status s = ReadAxes(f, node["axes"], *sensor, t); !s.ok()) return s;
  const std::vector<std::pair<const char*, Expr*>> numbers = {
      {"lever", &t.lever}, {"kp", &t.kp},           {"ki", &t.ki},
      {"kd", &t.kd},       {"rate_hz", &t.rate_hz}, {"lead_s", &t.lead_s}};
  for (const auto& [key, out] : numbers)
    if (Status s = ReadExprField(f, node[key], absl::StrCat("tracking.", key), d, *out); !s.ok())
      return s;
  const auto value = [&d](const std::string& n) { return d.Value(n); };
  if (!(t.lever.Eval(value) > 0)) return f.Error(node["lever"], "tracking.lever", "must be > 0 (m)");
  if (!(t.rate_hz.Eval(value) > 0))
    return f.Error(node["rate_hz"], "tracking.rate_hz", "must be > 0 (Hz)");
  if (t.lead_s.Eval(value) < 0) return f.Error(node["lead_s"], "tracking.lead_s", "must be >= 0 (s)");
  if (std::none_of(d.actuators.begin(), d.actuators.end(),
                   [](const Actuator& a) { return a.type == "tendon"; }))
    return f.Error(node, "tracking", "steers tendon actuators, and the robot has none");
  d.tracking = t;
  return absl::OkStatus();
}

}  // namespace gaitforge::robots
