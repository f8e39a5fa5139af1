// A descriptor's `electrical:` section (electrical_parser.h).
#include "robots/electrical_parser.h"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "robots/structure_parser.h"

namespace gaitforge::robots {
namespace {

using Status = absl::Status;

// A number field read as an expression and checked at the parameters' nominal values.
struct NumberField {
  const char* key;
  Expr* out;
  double lo, hi;
  bool lo_open;
  const char* allowed;
};

Status ReadNumbers(const YamlFields& f, const YAML::Node& node, const std::string& path,
                   const RobotDescriptor& d, const std::vector<NumberField>& fields) {
  const auto value = [&d](const std::string& n) { return d.Value(n); };
  for (const NumberField& n : fields) {
    const std::string field = absl::StrCat(path, ".", n.key);
    if (Status s = ReadExprField(f, node[n.key], field, d, *n.out); !s.ok()) return s;
    const double v = n.out->Eval(value);
    if (!(n.lo_open ? v > n.lo : v >= n.lo) || !(v <= n.hi))
      return f.Error(node[n.key], field, absl::StrCat("is ", v, "; must be ", n.allowed));
  }
  return absl::OkStatus();
}

Status ReadMotor(const YamlFields& f, const YAML::Node& node, const std::string& path,
                 RobotDescriptor& d, std::vector<std::string>& seen, Electrical::Motor& m) {
  if (Status s = f.CheckMap(node, path, {"actuators", "gear", "kt", "resistance"}); !s.ok())
    return s;
  auto names = f.StringList(node["actuators"], path + ".actuators");
  if (!names.ok()) return names.status();
  if (names->empty()) return f.Error(node, path + ".actuators", "name at least one servo actuator");
  for (const std::string& n : *names) {
    const auto a = std::find_if(d.actuators.begin(), d.actuators.end(),
                                [&n](const Actuator& x) { return x.name == n; });
    if (a == d.actuators.end() || a->type != "servo")
      return f.Error(node["actuators"], path + ".actuators",
                     absl::StrCat("'", n, "' is not a servo actuator of ", d.name));
    if (std::find(seen.begin(), seen.end(), n) != seen.end())
      return f.Error(node["actuators"], path + ".actuators",
                     absl::StrCat("'", n, "' has a motor already"));
    seen.push_back(n);
  }
  m.actuators = *names;
  return ReadNumbers(f, node, path, d,
                     {{"gear", &m.gear, 1, 1e4, false, ">= 1 (rotor turns per joint turn)"},
                      {"kt", &m.kt, 0, 1e3, true, "> 0 (N m/A at the rotor)"},
                      {"resistance", &m.resistance, 0, 1e3, false, ">= 0 (ohm per phase)"}});
}

}  // namespace

Status ParseElectrical(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d) {
  if (!node.IsMap()) return f.Error(node, "electrical", "expected a mapping");
  if (Status s = f.CheckMap(node, "electrical",
                            {"bus_voltage", "standby_current", "regen_efficiency", "motors",
                             "current_model", "current_model_rate_hz"});
      !s.ok())
    return s;
  Electrical e;
  e.mark = f.MarkOf(node);
  if (Status s = ReadNumbers(f, node, "electrical", d,
                             {{"bus_voltage", &e.bus_voltage, 0, 1e4, true, "> 0 (V)"},
                              {"standby_current", &e.standby_current, 0, 1e3, false, ">= 0 (A)"},
                              {"regen_efficiency", &e.regen_efficiency, 0, 1, false, "in [0, 1]"}});
      !s.ok())
    return s;
  if (node["current_model"]) {
    auto file = f.String(node["current_model"], "electrical.current_model");
    if (!file.ok()) return file.status();
    if (file->empty() || file->find("..") != std::string::npos)
      return f.Error(node["current_model"], "electrical.current_model",
                     "must name a file beside the descriptor (a gaitforge.mlp.v1 file)");
    e.current_model = *file;
    if (Status s = ReadNumbers(f, node, "electrical", d,
                               {{"current_model_rate_hz", &e.current_model_rate_hz, 0, 1e6, true,
                                 "> 0 (Hz: the rate of the recordings the model learned from)"}});
        !s.ok())
      return s;
  } else if (node["current_model_rate_hz"]) {
    return f.Error(node["current_model_rate_hz"], "electrical.current_model_rate_hz",
                   "belongs to a current_model");
  }
  const YAML::Node motors = node["motors"];
  if (!motors || !motors.IsSequence() || motors.size() == 0)
    return f.Error(node, "electrical.motors",
                   "missing (a list of motor types and their actuators)");
  std::vector<std::string> seen;
  for (size_t i = 0; i < motors.size(); ++i) {
    Electrical::Motor m;
    if (Status s = ReadMotor(f, motors[i], absl::StrCat("electrical.motors[", i, "]"), d, seen, m);
        !s.ok())
      return s;
    e.motors.push_back(std::move(m));
  }
  d.electrical = std::move(e);
  return absl::OkStatus();
}

}  // namespace gaitforge::robots
