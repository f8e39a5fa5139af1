#include "robots/structure_parser.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace gaitforge::robots {
namespace {

using Status = absl::Status;

std::vector<std::string> ParameterNames(const RobotDescriptor& d) {
  std::vector<std::string> names;
  for (const auto& p : d.parameters) names.push_back(p.name);
  return names;
}

// A number, a parameter name or a linear expression of them; its names must exist.
Status ReadExpr(const YamlFields& f, const YAML::Node& node, const std::string& path,
                const RobotDescriptor& d, Expr& out) {
  if (!node.IsDefined() || !node.IsScalar())
    return f.Error(node, path, "missing (a number, a parameter name or an expression)");
  auto text = f.Scalar(node, path);
  if (!text.ok()) return text.status();
  auto e = ParseExpr(*text);
  if (!e.ok()) return f.Error(node, path, std::string(e.status().message()));
  for (const auto& t : e->terms) {
    if (d.FindParameter(t.name) != nullptr) continue;
    return f.Error(node, path,
                   absl::StrCat("'", t.name, "' is not a parameter of this robot; nearest: ",
                                absl::StrJoin(Nearest(t.name, ParameterNames(d)), ", ")));
  }
  out = *e;
  return absl::OkStatus();
}

Status ReadVec(const YamlFields& f, const YAML::Node& node, const std::string& path,
               const RobotDescriptor& d, Vec3Expr& out) {
  if (!node.IsDefined() || !node.IsSequence() || node.size() != 3)
    return f.Error(node, path, "must be [x, y, z]");
  for (size_t i = 0; i < 3; ++i)
    if (Status s = ReadExpr(f, node[i], absl::StrCat(path, "[", i, "]"), d, out[i]); !s.ok())
      return s;
  return absl::OkStatus();
}

Status ReadOptional(const YamlFields& f, const YAML::Node& node, const std::string& key,
                    const std::string& path, const RobotDescriptor& d, std::optional<Expr>& out) {
  if (!node[key]) return absl::OkStatus();
  Expr e;
  if (Status s = ReadExpr(f, node[key], JoinPath(path, key), d, e); !s.ok()) return s;
  out = e;
  return absl::OkStatus();
}

Status CheckNewName(const YamlFields& f, const YAML::Node& node, const std::string& path,
                    const std::string& name, bool taken) {
  if (taken) return f.Error(node, path, absl::StrCat("the name '", name, "' is used twice"));
  return absl::OkStatus();
}

// A box's `size: [x, y, z]`, or a sphere's `radius` (its size then 2r along each axis).
Status ReadSize(const YamlFields& f, const YAML::Node& n, const std::string& path,
                const RobotDescriptor& d, Body& b) {
  const bool sphere = b.shape == "sphere";
  const char* wrong = sphere ? "size" : "radius";
  if (n[wrong])
    return f.Error(n[wrong], JoinPath(path, wrong),
                   sphere ? "a sphere takes radius, not size" : "a box takes size, not radius");
  if (!sphere) return ReadVec(f, n["size"], path + ".size", d, b.size);
  if (d.plane == "xz")
    return f.Error(n["shape"], path + ".shape", "a planar robot (plane: xz) is built of boxes");
  Expr r;
  if (Status s = ReadExpr(f, n["radius"], path + ".radius", d, r); !s.ok()) return s;
  r.constant *= 2;  // the expressions are linear: the diameter is 2 r
  for (auto& t : r.terms) t.coef *= 2;
  b.size = {r, r, r};
  return absl::OkStatus();
}

Status ParseBody(const YamlFields& f, const YAML::Node& n, const std::string& path,
                 RobotDescriptor& d) {
  if (Status s = f.CheckMap(n, path, {"name", "shape", "size", "radius", "mass", "position",
                                      "pitch", "friction", "contact_depth"});
      !s.ok())
    return s;
  Body b;
  b.mark = f.MarkOf(n);
  auto name = f.String(n["name"], path + ".name");
  if (!name.ok()) return name.status();
  b.name = *name;
  if (Status s = CheckNewName(f, n["name"], path + ".name", b.name, d.FindBody(b.name)); !s.ok())
    return s;
  if (b.name == kWorldBody)
    return f.Error(n["name"], path + ".name",
                   absl::StrCat("'", kWorldBody, "' names the fixed world frame in joints, not a body"));
  auto shape = f.String(n["shape"], path + ".shape");
  if (!shape.ok()) return shape.status();
  if (*shape != "box" && *shape != "sphere")
    return f.Error(n["shape"], path + ".shape", "must be box or sphere");
  b.shape = *shape;
  if (Status s = ReadSize(f, n, path, d, b); !s.ok()) return s;
  if (Status s = ReadExpr(f, n["mass"], path + ".mass", d, b.mass); !s.ok()) return s;
  if (Status s = ReadVec(f, n["position"], path + ".position", d, b.position); !s.ok()) return s;
  for (auto [key, out] : {std::pair{"pitch", &b.pitch}, std::pair{"friction", &b.friction},
                          std::pair{"contact_depth", &b.contact_depth}})
    if (Status s = ReadOptional(f, n, key, path, d, *out); !s.ok()) return s;
  d.bodies.push_back(std::move(b));
  return absl::OkStatus();
}

// A joint's body; `world_ok`: or kWorldBody, the fixed world frame.
Status ReadBodyName(const YamlFields& f, const YAML::Node& node, const std::string& path,
                    const RobotDescriptor& d, std::string& out, bool world_ok = false) {
  auto name = f.String(node, path);
  if (!name.ok()) return name.status();
  if (*name == kWorldBody && !world_ok)
    return f.Error(node, path, absl::StrCat("the world frame may only be a joint's first body"));
  if (*name != kWorldBody && d.FindBody(*name) == nullptr) {
    std::vector<std::string> known;
    for (const auto& b : d.bodies) known.push_back(b.name);
    return f.Error(node, path, absl::StrCat("no body named '", *name, "' (bodies: ",
                                            absl::StrJoin(known, ", "), ")"));
  }
  out = *name;
  return absl::OkStatus();
}

Status ParseAxis(const YamlFields& f, const YAML::Node& node, const std::string& path,
                 std::array<double, 3>& axis) {
  if (!node.IsDefined() || !node.IsSequence() || node.size() != 3)
    return f.Error(node, path, "must be [x, y, z]");
  double norm = 0;
  for (size_t i = 0; i < 3; ++i) {
    auto v = f.Number(node[i], absl::StrCat(path, "[", i, "]"));
    if (!v.ok()) return v.status();
    axis[i] = *v;
    norm += *v * *v;
  }
  if (std::fabs(std::sqrt(norm) - 1) > 1e-9) return f.Error(node, path, "must be a unit vector");
  return absl::OkStatus();
}

// A universal joint's spring field: one expression for both axes, or [AXIS1, AXIS2].
Status ReadPair(const YamlFields& f, const YAML::Node& n, const std::string& key,
                const std::string& path, const RobotDescriptor& d, std::optional<Expr>& first,
                std::optional<Expr>& second) {
  const YAML::Node node = n[key];
  if (!node) return absl::OkStatus();
  if (!node.IsSequence()) {
    if (Status s = ReadOptional(f, n, key, path, d, first); !s.ok()) return s;
    second = first;
    return absl::OkStatus();
  }
  if (node.size() != 2)
    return f.Error(node, JoinPath(path, key), "must be one value for both axes or [AXIS1, AXIS2]");
  Expr a, b;
  if (Status s = ReadExpr(f, node[0], JoinPath(path, key) + "[0]", d, a); !s.ok()) return s;
  if (Status s = ReadExpr(f, node[1], JoinPath(path, key) + "[1]", d, b); !s.ok()) return s;
  first = a;
  second = b;
  return absl::OkStatus();
}

// A universal joint's second axis and its springs (its stops are not supported).
Status ParseUniversal(const YamlFields& f, const YAML::Node& n, const std::string& path,
                      const RobotDescriptor& d, Joint& j) {
  if (n["lo"] || n["hi"])
    return f.Error(n["lo"] ? n["lo"] : n["hi"], path,
                   "a universal joint takes no stops (lo, hi); only a hinge does");
  if (Status s = ParseAxis(f, n["axis2"], path + ".axis2", j.axis2); !s.ok()) return s;
  const double dot = j.axis[0] * j.axis2[0] + j.axis[1] * j.axis2[1] + j.axis[2] * j.axis2[2];
  if (std::fabs(dot) > 1e-9)
    return f.Error(n["axis2"], path + ".axis2", "must be perpendicular to axis");
  for (auto [key, first, second] :
       {std::tuple{"stiffness", &j.stiffness, &j.stiffness2},
        std::tuple{"damping", &j.damping, &j.damping2}, std::tuple{"rest", &j.rest, &j.rest2}})
    if (Status s = ReadPair(f, n, key, path, d, *first, *second); !s.ok()) return s;
  return absl::OkStatus();
}

// A planar robot's compliant link: an axial and a bending spring-damper.
Status ParseSpringLink(const YamlFields& f, const YAML::Node& n, const std::string& path,
                       const RobotDescriptor& d, Joint& j) {
  if (d.plane != "xz")
    return f.Error(n["type"], path + ".type", "a spring_link needs a planar robot (plane: xz)");
  if (Status s = f.CheckMap(n, path, {"name", "type", "bodies", "anchor", "axis", "length",
                                      "axial_stiffness", "axial_damping_ratio", "stiffness",
                                      "damping_ratio"});
      !s.ok())
    return s;
  if (j.body1 == kWorldBody)
    return f.Error(n["bodies"], path + ".bodies", "a spring_link joins two bodies, not the world");
  if (j.axis[1] != 0)
    return f.Error(n["axis"], path + ".axis", "must lie in the robot's plane (y = 0)");
  for (auto [key, out] : {std::pair{"length", &j.length},
                          std::pair{"axial_stiffness", &j.axial_stiffness},
                          std::pair{"axial_damping_ratio", &j.axial_damping_ratio},
                          std::pair{"stiffness", &j.stiffness},
                          std::pair{"damping_ratio", &j.damping_ratio}}) {
    Expr e;
    if (Status s = ReadExpr(f, n[key], JoinPath(path, key), d, e); !s.ok()) return s;
    *out = e;
  }
  return absl::OkStatus();
}

Status ParseJoint(const YamlFields& f, const YAML::Node& n, const std::string& path,
                  RobotDescriptor& d) {
  if (Status s = f.CheckMap(n, path,
                            {"name", "type", "bodies", "anchor", "axis", "axis2", "stiffness",
                             "damping", "rest", "lo", "hi", "friction", "length", "axial_stiffness",
                             "axial_damping_ratio", "damping_ratio"});
      !s.ok())
    return s;
  Joint j;
  j.mark = f.MarkOf(n);
  auto name = f.String(n["name"], path + ".name");
  if (!name.ok()) return name.status();
  j.name = *name;
  if (Status s = CheckNewName(f, n["name"], path + ".name", j.name, d.FindJoint(j.name)); !s.ok())
    return s;
  auto type = f.String(n["type"], path + ".type");
  if (!type.ok()) return type.status();
  if (*type != "hinge" && *type != "universal" && *type != "fixed" && *type != "spring_link")
    return f.Error(n["type"], path + ".type", "must be hinge, universal, fixed or spring_link");
  j.type = *type;
  const YAML::Node bodies = n["bodies"];
  if (!bodies.IsSequence() || bodies.size() != 2)
    return f.Error(bodies, path + ".bodies", "must be [BODY1, BODY2]");
  if (Status s = ReadBodyName(f, bodies[0], path + ".bodies[0]", d, j.body1, true); !s.ok())
    return s;
  if (Status s = ReadBodyName(f, bodies[1], path + ".bodies[1]", d, j.body2); !s.ok()) return s;
  if (j.body1 == j.body2) return f.Error(bodies, path + ".bodies", "must name two bodies");
  if (j.type == "fixed") {
    // Welds body2 to body1 as built: nothing else to say.
    if (Status s = f.CheckMap(n, path, {"name", "type", "bodies"}); !s.ok()) return s;
    d.joints.push_back(std::move(j));
    return absl::OkStatus();
  }
  if (Status s = ReadVec(f, n["anchor"], path + ".anchor", d, j.anchor); !s.ok()) return s;
  if (Status s = ParseAxis(f, n["axis"], path + ".axis", j.axis); !s.ok()) return s;
  if (j.type != "hinge" && n["friction"])
    return f.Error(n["friction"], path + ".friction", "only a hinge has friction");
  if (j.type == "universal") {
    if (Status s = ParseUniversal(f, n, path, d, j); !s.ok()) return s;
    d.joints.push_back(std::move(j));
    return absl::OkStatus();
  }
  if (j.type == "spring_link") {
    if (Status s = ParseSpringLink(f, n, path, d, j); !s.ok()) return s;
    d.joints.push_back(std::move(j));
    return absl::OkStatus();
  }
  for (const char* key : {"length", "axial_stiffness", "axial_damping_ratio", "damping_ratio"})
    if (n[key]) return f.Error(n[key], JoinPath(path, key), "only a spring_link has it");
  if (n["axis2"]) return f.Error(n["axis2"], path + ".axis2", "only a universal joint has axis2");
  for (auto [key, out] : {std::pair{"stiffness", &j.stiffness}, std::pair{"damping", &j.damping},
                          std::pair{"rest", &j.rest}, std::pair{"lo", &j.lo},
                          std::pair{"hi", &j.hi}, std::pair{"friction", &j.friction}}) {
    if (Status s = ReadOptional(f, n, key, path, d, *out); !s.ok()) return s;
  }
  if (j.lo.has_value() != j.hi.has_value())
    return f.Error(n, path, "give both stops lo and hi, or neither");
  d.joints.push_back(std::move(j));
  return absl::OkStatus();
}

// A piston between two bodies' points (docs/robots.md, "actuators").
Status ParsePiston(const YamlFields& f, const YAML::Node& n, const std::string& path,
                   const RobotDescriptor& d, Actuator& a) {
  if (Status s = f.CheckMap(n, path, {"name", "type", "bodies", "attach1", "attach2", "force",
                                      "return_stiffness", "min_length", "max_length", "stop_erp",
                                      "stop_cfm", "overrun_tolerance"});
      !s.ok())
    return s;
  const YAML::Node bodies = n["bodies"];
  if (!bodies.IsSequence() || bodies.size() != 2)
    return f.Error(bodies, path + ".bodies", "must be [BODY1, BODY2]");
  if (Status s = ReadBodyName(f, bodies[0], path + ".bodies[0]", d, a.body1); !s.ok()) return s;
  if (Status s = ReadBodyName(f, bodies[1], path + ".bodies[1]", d, a.body2); !s.ok()) return s;
  if (a.body1 == a.body2) return f.Error(bodies, path + ".bodies", "must name two bodies");
  if (Status s = ReadVec(f, n["attach1"], path + ".attach1", d, a.attach1); !s.ok()) return s;
  if (Status s = ReadVec(f, n["attach2"], path + ".attach2", d, a.attach2); !s.ok()) return s;
  for (auto [key, out] :
       {std::pair{"force", &a.force}, std::pair{"return_stiffness", &a.return_stiffness},
        std::pair{"min_length", &a.min_length}, std::pair{"max_length", &a.max_length},
        std::pair{"stop_erp", &a.stop_erp}, std::pair{"stop_cfm", &a.stop_cfm},
        std::pair{"overrun_tolerance", &a.overrun_tolerance}})
    if (Status s = ReadExpr(f, n[key], JoinPath(path, key), d, *out); !s.ok()) return s;
  return absl::OkStatus();
}

Status ParseTendon(const YamlFields& f, const YAML::Node& n, const std::string& path,
                   const RobotDescriptor& d, Actuator& a) {
  if (Status s = f.CheckMap(n, path, {"name", "type", "bodies", "attach", "pull", "max_force"});
      !s.ok())
    return s;
  const YAML::Node bodies = n["bodies"];
  if (!bodies.IsSequence() || bodies.size() != 2)
    return f.Error(bodies, path + ".bodies", "must be [BASE, END]: the body (or world) it is pulled from, the body its rod is fixed to");
  if (Status s = ReadBodyName(f, bodies[0], path + ".bodies[0]", d, a.body1, true); !s.ok())
    return s;
  if (Status s = ReadBodyName(f, bodies[1], path + ".bodies[1]", d, a.body2); !s.ok()) return s;
  if (a.body1 == a.body2) return f.Error(bodies, path + ".bodies", "must name two bodies");
  if (Status s = ReadVec(f, n["attach"], path + ".attach", d, a.attach2); !s.ok()) return s;
  if (Status s = ReadVec(f, n["pull"], path + ".pull", d, a.pull); !s.ok()) return s;
  return ReadExpr(f, n["max_force"], path + ".max_force", d, a.max_force);
}

// A servo's control law: a speed command (gain, max_speed) or a PD torque (kp, kd), not both.
Status ReadServoControl(const YamlFields& f, const YAML::Node& n, const std::string& path,
                        const RobotDescriptor& d, Actuator& a) {
  const bool pd = n["kp"] || n["kd"];
  for (const char* key : {"gain", "max_speed"})
    if (pd && n[key])
      return f.Error(n[key], JoinPath(path, key),
                     "a PD servo (kp, kd) has no speed command (gain, max_speed)");
  if (!pd) {
    for (auto [key, out] : {std::pair{"gain", &a.gain}, std::pair{"max_speed", &a.max_speed}})
      if (Status s = ReadExpr(f, n[key], JoinPath(path, key), d, *out); !s.ok()) return s;
    return absl::OkStatus();
  }
  Expr kp, kd;
  if (Status s = ReadExpr(f, n["kp"], JoinPath(path, "kp"), d, kp); !s.ok()) return s;
  if (Status s = ReadExpr(f, n["kd"], JoinPath(path, "kd"), d, kd); !s.ok()) return s;
  a.kp = kp;
  a.kd = kd;
  return absl::OkStatus();
}

Status ParseActuator(const YamlFields& f, const YAML::Node& n, const std::string& path,
                     RobotDescriptor& d) {
  Actuator a;
  a.mark = f.MarkOf(n);
  for (auto [key, out] : {std::pair{"name", &a.name}, std::pair{"type", &a.type}}) {
    auto v = f.String(n[key], JoinPath(path, key));
    if (!v.ok()) return v.status();
    *out = *v;
  }
  if (a.type == "piston") {
    if (Status s = ParsePiston(f, n, path, d, a); !s.ok()) return s;
    d.actuators.push_back(std::move(a));
    return absl::OkStatus();
  }
  if (a.type == "tendon") {
    if (Status s = ParseTendon(f, n, path, d, a); !s.ok()) return s;
    d.actuators.push_back(std::move(a));
    return absl::OkStatus();
  }
  if (a.type != "servo")
    return f.Error(n["type"], path + ".type", "must be servo, piston or tendon");
  if (Status s = f.CheckMap(n, path, {"name", "type", "joint", "gain", "max_speed", "kp", "kd",
                                      "max_torque", "lag_s"});
      !s.ok())
    return s;
  auto joint = f.String(n["joint"], path + ".joint");
  if (!joint.ok()) return joint.status();
  a.joint = *joint;
  if (const Joint* j = d.FindJoint(a.joint); j == nullptr || j->type != "hinge")
    return f.Error(n["joint"], path + ".joint",
                   absl::StrCat(j ? "a servo turns a hinge; '" : "no joint named '", a.joint,
                                j ? "' is fixed" : "'"));
  if (Status s = ReadServoControl(f, n, path, d, a); !s.ok()) return s;
  for (auto [key, out] : {std::pair{"max_torque", &a.max_torque}, std::pair{"lag_s", &a.lag_s}}) {
    if (Status s = ReadExpr(f, n[key], JoinPath(path, key), d, *out); !s.ok()) return s;
  }
  d.actuators.push_back(std::move(a));
  return absl::OkStatus();
}

template <typename Fn>
Status ParseList(const YamlFields& f, const YAML::Node& node, const std::string& key,
                 RobotDescriptor& d, Fn parse_one) {
  if (!node[key]) return absl::OkStatus();
  if (!node[key].IsSequence()) return f.Error(node[key], key, "must be a list");
  return f.ForEachItem(node[key], key, [&](const YAML::Node& item, const std::string& path) {
    return parse_one(f, item, path, d);
  });
}

// The controller drives exactly the declared actuators, when the robot declares them.
Status CheckControllerActuators(const YamlFields& f, const YAML::Node& root,
                                const RobotDescriptor& d) {
  if (d.actuators.empty()) return absl::OkStatus();
  std::vector<std::string> declared;
  for (const auto& a : d.actuators) declared.push_back(a.name);
  std::vector<std::string> driven = d.controller.actuators;
  std::vector<std::string> sorted_declared = declared;
  std::sort(driven.begin(), driven.end());
  std::sort(sorted_declared.begin(), sorted_declared.end());
  if (driven == sorted_declared) return absl::OkStatus();
  return f.Error(root["controller"]["actuators"], "controller.actuators",
                 absl::StrCat("must name each declared actuator once (",
                              absl::StrJoin(declared, ", "), "); its genes follow them"));
}

}  // namespace

Status ReadVec3(const YamlFields& f, const YAML::Node& node, const std::string& path,
                const RobotDescriptor& d, Vec3Expr& out) {
  return ReadVec(f, node, path, d, out);
}

Status ReadExprField(const YamlFields& f, const YAML::Node& node, const std::string& path,
                     const RobotDescriptor& d, Expr& out) {
  return ReadExpr(f, node, path, d, out);
}

Status ParseStructure(const YamlFields& f, const YAML::Node& root, RobotDescriptor& d) {
  if (root["plane"]) {
    auto plane = f.String(root["plane"], "plane");
    if (!plane.ok()) return plane.status();
    if (*plane != "xz") return f.Error(root["plane"], "plane", "must be xz (or left out: 3-D)");
    d.plane = *plane;
  }
  if (root["self_contact"]) {
    auto on = f.Bool(root["self_contact"], "self_contact");
    if (!on.ok()) return on.status();
    d.self_contact = *on;
  }
  if (Status s = ParseList(f, root, "bodies", d, ParseBody); !s.ok()) return s;
  if (Status s = ParseList(f, root, "joints", d, ParseJoint); !s.ok()) return s;
  if (Status s = ParseList(f, root, "actuators", d, ParseActuator); !s.ok()) return s;
  if (root["ground"]) {
    const YAML::Node g = root["ground"];
    if (Status s = f.CheckMap(g, "ground", {"friction", "erp", "cfm", "friction_load"}); !s.ok())
      return s;
    Ground ground;
    if (g["friction_load"]) {
      auto load = f.String(g["friction_load"], "ground.friction_load");
      if (!load.ok()) return load.status();
      if (*load != "corner" && *load != "body")
        return f.Error(g["friction_load"], "ground.friction_load", "must be corner or body");
      ground.friction_load = *load;
    }
    if (Status s = ReadExpr(f, g["friction"], "ground.friction", d, ground.friction); !s.ok())
      return s;
    if (Status s = ReadExpr(f, g["erp"], "ground.erp", d, ground.erp); !s.ok()) return s;
    if (Status s = ReadExpr(f, g["cfm"], "ground.cfm", d, ground.cfm); !s.ok()) return s;
    d.ground = ground;
  }
  return CheckControllerActuators(f, root, d);
}

}  // namespace gaitforge::robots
