#include "robots/descriptor_parser.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "robots/controllers.h"
#include "robots/electrical_parser.h"
#include "robots/relations.h"
#include "robots/structure_parser.h"
#include "robots/suspects_parser.h"
#include "robots/tracking_parser.h"
#include "robots/yaml_fields.h"

namespace gaitforge::robots {
namespace {

using Status = absl::Status;

Status ParseParameter(const YamlFields& f, const YAML::Node& node, const std::string& path,
                      RobotDescriptor& d) {
  if (Status s = f.CheckMap(node, path,
                            {"value", "range", "unit", "doc", "integer", "calibrate", "infinite"});
      !s.ok())
    return s;
  Parameter p;
  p.name = path;
  if (Status s = f.Range(node["range"], path + ".range", p.lo, p.hi); !s.ok()) return s;
  if (node["unit"]) {
    auto u = f.String(node["unit"], path + ".unit");
    if (!u.ok()) return u.status();
    p.unit = *u;
  }
  for (auto [key, out] : {std::pair{"doc", &p.doc}, std::pair{"infinite", &p.infinite}}) {
    if (!node[key]) continue;
    auto t = f.String(node[key], JoinPath(path, key));
    if (!t.ok()) return t.status();
    *out = *t;
  }
  for (auto [key, out] : {std::pair{"integer", &p.integer}, std::pair{"calibrate", &p.calibratable}}) {
    if (!node[key]) continue;
    auto b = f.Bool(node[key], JoinPath(path, key));
    if (!b.ok()) return b.status();
    *out = *b;
  }
  auto v = f.Number(node["value"], path + ".value", !p.infinite.empty());
  if (!v.ok()) return v.status();
  p.value = *v;
  p.mark = f.MarkOf(node["value"]);
  if (std::string bad = p.Check(p.value); !bad.empty()) return f.Error(node["value"], "", bad);
  d.parameters.push_back(std::move(p));
  return absl::OkStatus();
}

// A group is a mapping of groups and parameters; a parameter is a mapping with "value".
Status ParseParameters(const YamlFields& f, const YAML::Node& node, const std::string& path,
                       RobotDescriptor& d) {
  if (Status s = f.CheckNoDuplicates(node, path); !s.ok()) return s;
  for (const auto& kv : node) {
    const std::string child = JoinPath(path, kv.first.Scalar());
    if (!kv.second.IsMap()) {
      return f.Error(kv.second, child,
                     "must be a parameter {value, range, unit, doc} or a group of them");
    }
    Status s = kv.second["value"] ? ParseParameter(f, kv.second, child, d)
                                  : ParseParameters(f, kv.second, child, d);
    if (!s.ok()) return s;
  }
  return absl::OkStatus();
}

// Every parameter name in `names` must exist; `path` is where the list is.
Status CheckNames(const YamlFields& f, const YAML::Node& node, const std::string& path,
                  const std::vector<std::string>& names, const RobotDescriptor& d) {
  std::vector<std::string> known;
  for (const auto& p : d.parameters) known.push_back(p.name);
  for (const auto& n : names) {
    if (d.FindParameter(n) != nullptr) continue;
    return f.Error(node, path,
                   absl::StrCat("'", n, "' is not a parameter of this robot; nearest: ",
                                absl::StrJoin(Nearest(n, known), ", ")));
  }
  return absl::OkStatus();
}

// counts: {NAME: {value: N, range: [LO, HI], doc: ...}}: whole numbers, set as template
// variables for the rest of the file.
Status ParseCounts(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d) {
  if (!node.IsMap()) return f.Error(node, "counts", "must be a mapping of NAME: {value, range}");
  if (Status s = f.CheckNoDuplicates(node, "counts"); !s.ok()) return s;
  for (const auto& kv : node) {
    const std::string path = JoinPath("counts", kv.first.Scalar());
    if (Status s = f.CheckMap(kv.second, path, {"value", "range", "doc"}); !s.ok()) return s;
    RobotDescriptor::Count c;
    c.name = kv.first.Scalar();
    double value = 0, lo = 0, hi = 0;
    auto v = f.Number(kv.second["value"], path + ".value");
    if (!v.ok()) return v.status();
    value = *v;
    if (Status s = f.Range(kv.second["range"], path + ".range", lo, hi); !s.ok()) return s;
    if (value != std::round(value) || lo != std::round(lo) || hi != std::round(hi))
      return f.Error(kv.second, path, "value and range must be whole numbers");
    if (value < lo || value > hi)
      return f.Error(kv.second["value"], path + ".value",
                     absl::StrCat(value, " is outside its range [", lo, ", ", hi, "]"));
    if (kv.second["doc"]) {
      auto doc = f.String(kv.second["doc"], path + ".doc");
      if (!doc.ok()) return doc.status();
      c.doc = *doc;
    }
    c.value = static_cast<int>(value);
    c.lo = static_cast<int>(lo);
    c.hi = static_cast<int>(hi);
    f.SetVariable(c.name, value);
    d.counts.push_back(c);
  }
  return absl::OkStatus();
}

Status ParseScales(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d) {
  if (Status s = f.CheckNoDuplicates(node, "scales"); !s.ok()) return s;
  for (const auto& kv : node) {
    const std::string path = JoinPath("scales", kv.first.Scalar());
    if (Status s = f.CheckMap(kv.second, path, {"doc", "multiplies"}); !s.ok()) return s;
    Scale sc;
    sc.name = "scale." + kv.first.Scalar();
    if (kv.second["doc"]) {
      auto doc = f.String(kv.second["doc"], path + ".doc");
      if (!doc.ok()) return doc.status();
      sc.doc = *doc;
    }
    auto m = f.StringList(kv.second["multiplies"], path + ".multiplies");
    if (!m.ok()) return m.status();
    if (Status s = CheckNames(f, kv.second["multiplies"], path + ".multiplies", *m, d); !s.ok())
      return s;
    sc.multiplies = *m;
    d.scales.push_back(std::move(sc));
  }
  return absl::OkStatus();
}

Status ParseController(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d) {
  if (!node.IsMap()) return f.Error(node, "controller", "expected a mapping");
  auto kind = f.String(node["kind"], "controller.kind");
  if (!kind.ok()) return kind.status();
  const ControllerKind* k = FindControllerKind(*kind);
  if (k == nullptr) {
    return f.Error(node["kind"], "controller.kind",
                   absl::StrCat("unknown kind '", *kind,
                                "' (known: ", absl::StrJoin(ControllerKindNames(), ", "), ")"));
  }
  std::vector<std::string> allowed = {"kind", "actuators"};
  allowed.insert(allowed.end(), k->range_keys.begin(), k->range_keys.end());
  allowed.insert(allowed.end(), k->value_keys.begin(), k->value_keys.end());
  if (Status s = f.CheckMap(node, "controller", allowed); !s.ok()) return s;
  Controller& c = d.controller;
  c.kind = *kind;
  // A kind without ranges (hold) may drive nothing: then `actuators` is left out.
  if (node["actuators"] || !k->range_keys.empty()) {
    auto acts = f.StringList(node["actuators"], "controller.actuators");
    if (!acts.ok()) return acts.status();
    c.actuators = *acts;
  }
  if (k->actuators > 0 && static_cast<int>(c.actuators.size()) != k->actuators)
    return f.Error(node["actuators"], "controller.actuators",
                   absl::StrCat("kind ", c.kind, " drives exactly ", k->actuators, " actuators, got ",
                                c.actuators.size()));
  for (const std::string& key : k->range_keys) {
    const std::string path = "controller." + key;
    std::array<double, 2> r{};
    if (Status s = f.Range(node[key], path, r[0], r[1]); !s.ok()) return s;
    if ((key == "period_s" || key == "frequency_hz") && !(r[0] > 0))
      return f.Error(node[key], path, "must be > 0");
    c.ranges[key] = r;
  }
  for (const std::string& key : k->value_keys) {
    Expr e;
    if (Status s = ReadExprField(f, node[key], "controller." + key, d, e); !s.ok()) return s;
    c.values[key] = e.Eval([&d](const std::string& n) { return d.Value(n); });
  }
  c.genes = k->genes(c);
  return absl::OkStatus();
}

// A generic robot's markers sit on bodies: `bodies` parallel to `names`, `offset` in the
// body frame.
Status ParseMarkerBodies(const YamlFields& f, const YAML::Node& node, const std::string& path,
                         const RobotDescriptor& d, Sensor& s) {
  if (!node["bodies"]) {
    if (node["offset"]) return f.Error(node["offset"], path + ".offset", "needs bodies");
    return absl::OkStatus();
  }
  auto bodies = f.StringList(node["bodies"], path + ".bodies");
  if (!bodies.ok()) return bodies.status();
  if (bodies->size() != s.names.size())
    return f.Error(node["bodies"], path + ".bodies", "must name one body per marker");
  for (const auto& b : *bodies)
    if (d.FindBody(b) == nullptr)
      return f.Error(node["bodies"], path + ".bodies", absl::StrCat("no body named '", b, "'"));
  s.bodies = *bodies;
  if (node["offset"]) {
    Vec3Expr offset;
    if (Status st = ReadVec3(f, node["offset"], path + ".offset", d, offset); !st.ok()) return st;
    s.offset = offset;
  }
  return absl::OkStatus();
}

Status ParseSensor(const YamlFields& f, const YAML::Node& node, const std::string& path,
                   RobotDescriptor& d) {
  if (Status s = f.CheckMap(node, path, {"kind", "names", "axes", "spacing", "bodies", "offset"});
      !s.ok())
    return s;
  Sensor s;
  auto kind = f.String(node["kind"], path + ".kind");
  if (!kind.ok()) return kind.status();
  if (*kind != "marker" && *kind != "joint_angle" && *kind != "joint_torque" &&
      *kind != "joint_rate")
    return f.Error(node["kind"], path + ".kind",
                   "must be marker, joint_angle, joint_torque or joint_rate");
  s.kind = *kind;
  auto names = f.StringList(node["names"], path + ".names");
  if (!names.ok()) return names.status();
  s.names = *names;
  if (s.kind == "marker") {
    auto axes = f.StringList(node["axes"], path + ".axes");
    if (!axes.ok()) return axes.status();
    for (const auto& a : *axes)
      if (a != "x" && a != "y" && a != "z")
        return f.Error(node["axes"], path + ".axes", "each axis must be x, y or z");
    s.axes = *axes;
    if (node["spacing"]) {
      auto sp = f.String(node["spacing"], path + ".spacing");
      if (!sp.ok()) return sp.status();
      if (Status st = CheckNames(f, node["spacing"], path + ".spacing", {*sp}, d); !st.ok())
        return st;
      s.spacing = *sp;
    }
    if (Status st = ParseMarkerBodies(f, node, path, d, s); !st.ok()) return st;
  } else if (node["axes"] || node["spacing"] || node["bodies"] || node["offset"]) {
    return f.Error(node, path, "axes, spacing, bodies and offset belong to markers");
  } else if (s.kind != "joint_angle") {  // a servo's torque or its joint's rate
    for (const auto& n : s.names)
      if (std::none_of(d.actuators.begin(), d.actuators.end(),
                       [&n](const Actuator& a) { return a.name == n && a.type == "servo"; }))
        return f.Error(
            node["names"], path + ".names",
            absl::StrCat("no servo actuator named '", n, "' (", s.kind, " names servos)"));
  } else {
    for (const auto& n : s.names)
      if (const Joint* j = d.FindJoint(n); !d.joints.empty() && (j == nullptr || j->type == "fixed"))
        return f.Error(node["names"], path + ".names",
                       absl::StrCat(j ? "a fixed joint has no angle: '" : "no joint named '", n, "'"));
  }
  d.sensors.push_back(std::move(s));
  return absl::OkStatus();
}

Status ParseSensors(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d) {
  if (!node.IsSequence()) return f.Error(node, "sensors", "must be a list of sensor groups");
  for (size_t i = 0; i < node.size(); ++i) {
    if (Status s = ParseSensor(f, node[i], absl::StrCat("sensors[", i, "]"), d); !s.ok()) return s;
  }
  std::vector<std::string> seen;
  for (const auto& ch : d.Channels()) {
    if (std::find(seen.begin(), seen.end(), ch) != seen.end())
      return f.Error(node, "sensors", absl::StrCat("channel ", ch, " is declared twice"));
    seen.push_back(ch);
  }
  return absl::OkStatus();
}

// `objectives: {distance: NAME, calibration: NAME}`: the robot's own names for the
// robot-agnostic objectives bound to it; each a dotted name outside robot.* and analytic.*.
Status ParseObjectiveNames(const YamlFields& f, const YAML::Node& root, RobotDescriptor& d) {
  const YAML::Node node = root["objectives"];
  if (!node) return absl::OkStatus();
  if (Status s = f.CheckMap(node, "objectives", {"distance", "calibration"}); !s.ok()) return s;
  for (auto [key, out] : {std::pair{"distance", &d.distance_objective},
                          std::pair{"calibration", &d.calibration_objective}}) {
    if (!node[key]) continue;
    auto name = f.String(node[key], JoinPath("objectives", key));
    if (!name.ok()) return name.status();
    const size_t dot = name->find('.');
    if (dot == std::string::npos || dot == 0 || dot + 1 == name->size() ||
        name->rfind("robot.", 0) == 0 || name->rfind("analytic.", 0) == 0)
      return f.Error(node[key], JoinPath("objectives", key),
                     "must be a dotted name such as " + d.name + "." + key +
                         ", outside robot.* and analytic.*");
    *out = *name;
  }
  return absl::OkStatus();
}

Status ParseHeader(const YamlFields& f, const YAML::Node& root, RobotDescriptor& d) {
  auto format = f.String(root["format"], "format");
  if (!format.ok()) return format.status();
  if (*format != kDescriptorFormat)
    return f.Error(root["format"], "format", absl::StrCat("must be \"", kDescriptorFormat, "\""));
  for (auto [key, out] : {std::pair{"name", &d.name}, std::pair{"model", &d.model}}) {
    auto v = f.String(root[key], key);
    if (!v.ok()) return v.status();
    *out = *v;
  }
  for (auto [key, out] : {std::pair{"summary", &d.summary}, std::pair{"paper", &d.paper}}) {
    if (!root[key]) continue;
    auto v = f.String(root[key], key);
    if (!v.ok()) return v.status();
    *out = *v;
  }
  if (Status s = ParseObjectiveNames(f, root, d); !s.ok()) return s;
  if (!root["figures"]) return absl::OkStatus();
  auto figures = f.StringList(root["figures"], "figures");
  if (!figures.ok()) return figures.status();
  for (size_t i = 0; i < figures->size(); ++i)
    if (std::find(kFigureKinds.begin(), kFigureKinds.end(), (*figures)[i]) == kFigureKinds.end())
      return f.Error(root["figures"][i], absl::StrCat("figures[", i, "]"),
                     absl::StrCat("'", (*figures)[i], "' is not a figure kind (known: ",
                                  absl::StrJoin(kFigureKinds, ", "), ")"));
  d.figures = *figures;
  return absl::OkStatus();
}

absl::StatusOr<RobotDescriptor> FromYaml(const YAML::Node& root, const std::string& source) {
  YamlFields f(source);
  if (Status s =
          f.CheckMap(root, "", {"format",   "name",       "summary",    "paper",   "model",
                                "figures",  "objectives", "parameters", "counts",  "scales",
                                "suspects", "relations",  "controller", "sensors", "bodies",
                                "joints",   "actuators",  "ground",     "plane",   "self_contact",
                                "tracking", "electrical", "ruled_out"});
      !s.ok())
    return s;
  RobotDescriptor d;
  d.source = source;
  if (Status s = ParseHeader(f, root, d); !s.ok()) return s;
  if (root["counts"])
    if (Status s = ParseCounts(f, root["counts"], d); !s.ok()) return s;
  if (!root["parameters"].IsMap())
    return f.Error(root["parameters"], "parameters", "missing (a mapping of the robot's numbers)");
  if (Status s = ParseParameters(f, root["parameters"], "", d); !s.ok()) return s;
  if (root["scales"])
    if (Status s = ParseScales(f, root["scales"], d); !s.ok()) return s;
  if (root["suspects"])
    if (Status s = ParseSuspects(f, root["suspects"], d); !s.ok()) return s;
  if (root["ruled_out"])
    if (Status s = ParseRuledOut(f, root["ruled_out"], d); !s.ok()) return s;
  if (root["relations"])
    if (Status s = ParseRelations(f, root["relations"], d); !s.ok()) return s;
  if (!root["controller"])
    return f.Error(root, "controller", "missing (the controller and its gene space)");
  if (Status s = ParseController(f, root["controller"], d); !s.ok()) return s;
  if (Status s = ParseStructure(f, root, d); !s.ok()) return s;
  if (root["sensors"])
    if (Status s = ParseSensors(f, root["sensors"], d); !s.ok()) return s;
  if (root["tracking"])
    if (Status s = ParseTracking(f, root["tracking"], d); !s.ok()) return s;
  if (root["electrical"])
    if (Status s = ParseElectrical(f, root["electrical"], d); !s.ok()) return s;
  if (Status s = d.CheckRelations([&d](const std::string& n) { return d.Value(n); }); !s.ok())
    return s;
  return d;
}

}  // namespace

absl::StatusOr<RobotDescriptor> ParseDescriptor(const std::string& text,
                                                const std::string& source) {
  auto root = LoadYaml(text, source);
  if (!root.ok()) return root.status();
  try {
    return FromYaml(*root, source);
  } catch (const YAML::Exception& e) {  // a node of an unexpected kind somewhere
    return absl::InvalidArgumentError(absl::StrCat(source, ":", e.mark.line + 1, ":",
                                                   e.mark.column + 1, ": ", e.msg));
  }
}

absl::StatusOr<RobotDescriptor> LoadDescriptor(const std::string& path) {
  if (std::filesystem::is_directory(path))
    return absl::InvalidArgumentError(absl::StrCat(
        path, ": is a directory; give its robot.yaml (", path, "/robot.yaml)"));
  std::ifstream in(path);
  if (!in) return absl::NotFoundError(absl::StrCat(path, ": cannot open the robot descriptor"));
  std::stringstream text;
  text << in.rdbuf();
  return ParseDescriptor(text.str(), path);
}

}  // namespace gaitforge::robots
