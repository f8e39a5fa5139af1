#include "workers/models/mujoco/mjcf.h"

#include <cmath>
#include <map>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"

namespace gaitforge::mujoco {
namespace {

using generic::ParamValues;

double Eval(const robots::Expr& e, const ParamValues& v) {
  return e.Eval([&v](const std::string& n) { return v(n); });
}

std::array<double, 3> Eval(const robots::Vec3Expr& e, const ParamValues& v) {
  return {Eval(e[0], v), Eval(e[1], v), Eval(e[2], v)};
}

std::string Num(double x) { return absl::StrFormat("%.10g", x); }
std::string Vec(const std::array<double, 3>& a) {
  return absl::StrCat(Num(a[0]), " ", Num(a[1]), " ", Num(a[2]));
}

// A pose in the world: position and pitch about +y (robots::Body).
struct Pose {
  std::array<double, 3> p{};
  double pitch = 0;
  // World vector w expressed in this pose's frame: R_y(pitch)^T w.
  std::array<double, 3> ToLocal(const std::array<double, 3>& w) const {
    const double c = std::cos(pitch), s = std::sin(pitch);
    return {c * w[0] - s * w[2], w[1], s * w[0] + c * w[2]};
  }
  std::array<double, 3> PointToLocal(const std::array<double, 3>& w) const {
    return ToLocal({w[0] - p[0], w[1] - p[1], w[2] - p[2]});
  }
};

struct Tree {
  std::vector<Pose> pose;                      // per body
  std::vector<int> parent;                     // per body, -1: a root
  std::vector<int> joint_of;                   // per body: the joint nesting it, -1: none
  std::multimap<int, int> children;            // parent -> child bodies
};

absl::StatusOr<Tree> MakeTree(const robots::RobotDescriptor& d, const ParamValues& v) {
  Tree t;
  const size_t n = d.bodies.size();
  t.parent.assign(n, -1);
  t.joint_of.assign(n, -1);
  std::map<std::string, int> index;
  for (size_t i = 0; i < n; ++i) {
    index[d.bodies[i].name] = static_cast<int>(i);
    t.pose.push_back({Eval(d.bodies[i].position, v), d.bodies[i].pitch ? Eval(*d.bodies[i].pitch, v) : 0.0});
  }
  for (size_t j = 0; j < d.joints.size(); ++j) {
    const int b = index.at(d.joints[j].body2);
    if (t.joint_of[b] >= 0)
      return absl::InvalidArgumentError(absl::StrCat(
          d.joints[j].mark.ToString(), ": body ", d.joints[j].body2,
          " is the second body of two joints; a MuJoCo build needs a tree"));
    t.joint_of[b] = static_cast<int>(j);
    if (d.joints[j].body1 == robots::kWorldBody) continue;  // a root held by the world
    const int a = index.at(d.joints[j].body1);
    t.parent[b] = a;
    t.children.emplace(a, b);
  }
  for (size_t i = 0; i < n; ++i)  // a cycle leaves no root above it
    for (int up = t.parent[i], hops = 0; up >= 0; up = t.parent[up])
      if (++hops > static_cast<int>(n))
        return absl::InvalidArgumentError(d.source + ": the joints form a loop; a MuJoCo build needs a tree");
  return t;
}

struct Writer {
  const robots::RobotDescriptor& d;
  const ParamValues& v;
  const Tree& t;
  std::ostringstream out;

  absl::Status Body(int i, int depth);
  absl::Status Hinge(const robots::Joint& j, const Pose& child, const std::string& pad);
  // A universal joint: two hinges in the child, the first about axis, the second about
  // axis2 as the first has turned it, named by their channels (NAME.angle1, NAME.angle2).
  void Universal(const robots::Joint& j, const Pose& child, const std::string& pad);
  void OneHinge(const std::string& name, const Pose& child, const robots::Joint& j,
                const std::array<double, 3>& axis, const std::optional<robots::Expr>& k,
                const std::optional<robots::Expr>& rest, const std::optional<robots::Expr>& c,
                const std::string& pad);
};

void Writer::OneHinge(const std::string& name, const Pose& child, const robots::Joint& j,
                      const std::array<double, 3>& axis, const std::optional<robots::Expr>& k,
                      const std::optional<robots::Expr>& rest,
                      const std::optional<robots::Expr>& c, const std::string& pad) {
  // MuJoCo's hinge turns the child about the axis; ODE's angle (generic_world) is measured
  // the other way round, so the axis is reversed and both report the same angle.
  out << pad << "<joint name=\"" << name << "\" type=\"hinge\" pos=\""
      << Vec(child.PointToLocal(Eval(j.anchor, v))) << "\" axis=\""
      << Vec(child.ToLocal({-axis[0], -axis[1], -axis[2]})) << "\"";
  if (k) out << " stiffness=\"" << Num(Eval(*k, v)) << "\"";
  if (rest) out << " springref=\"" << Num(Eval(*rest, v)) << "\"";
  if (c) out << " damping=\"" << Num(Eval(*c, v)) << "\"";
}

void Writer::Universal(const robots::Joint& j, const Pose& child, const std::string& pad) {
  OneHinge(j.name + ".angle1", child, j, j.axis, j.stiffness, j.rest, j.damping, pad);
  out << "/>\n";
  OneHinge(j.name + ".angle2", child, j, j.axis2, j.stiffness2, j.rest2, j.damping2, pad);
  out << "/>\n";
}

absl::Status Writer::Hinge(const robots::Joint& j, const Pose& child, const std::string& pad) {
  OneHinge(j.name, child, j, j.axis, j.stiffness, j.rest, j.damping, pad);
  if (j.friction) out << " frictionloss=\"" << Num(Eval(*j.friction, v)) << "\"";
  if (j.lo || j.hi) {
    const double lo = j.lo ? Eval(*j.lo, v) : -M_PI, hi = j.hi ? Eval(*j.hi, v) : M_PI;
    if (!(lo < hi))
      return absl::InvalidArgumentError(absl::StrCat(j.mark.ToString(), ": joint ", j.name,
                                                     "'s stops need lo < hi"));
    out << " limited=\"true\" range=\"" << Num(lo) << " " << Num(hi) << "\"";
  }
  out << "/>\n";
  return absl::OkStatus();
}

absl::Status Writer::Body(int i, int depth) {
  const robots::Body& b = d.bodies[i];
  const Pose& me = t.pose[i];
  const std::string pad(2 * depth + 4, ' ');
  std::array<double, 3> pos = me.p;
  double pitch = me.pitch;
  if (t.parent[i] >= 0) {
    pos = t.pose[t.parent[i]].PointToLocal(me.p);
    pitch -= t.pose[t.parent[i]].pitch;
  }
  out << pad << "<body name=\"" << b.name << "\" pos=\"" << Vec(pos) << "\" quat=\""
      << Num(std::cos(pitch / 2)) << " 0 " << Num(std::sin(pitch / 2)) << " 0\">\n";
  const std::string in = pad + "  ";
  if (t.joint_of[i] < 0) {
    out << in << "<freejoint name=\"" << b.name << "_free\"/>\n";
  } else if (const robots::Joint& j = d.joints[t.joint_of[i]]; j.type == "hinge") {
    if (absl::Status s = Hinge(j, me, in); !s.ok()) return s;
  } else if (j.type == "universal") {
    Universal(j, me, in);
  }
  const auto size = Eval(b.size, v);
  const double m = Eval(b.mass, v);
  if (!(size[0] > 0 && size[1] > 0 && size[2] > 0 && m > 0))
    return absl::InvalidArgumentError(
        absl::StrCat(b.mark.ToString(), ": body ", b.name, " needs a positive size and mass"));
  const double xx = size[0] * size[0], yy = size[1] * size[1], zz = size[2] * size[2];
  const bool sphere = b.shape == "sphere";  // size: its diameter on each axis
  const double i_sphere = m * xx / 10;       // 2/5 m r^2
  out << in << "<inertial pos=\"0 0 0\" mass=\"" << Num(m) << "\" diaginertia=\""
      << Num(sphere ? i_sphere : m * (yy + zz) / 12) << " "
      << Num(sphere ? i_sphere : m * (xx + zz) / 12) << " "
      << Num(sphere ? i_sphere : m * (xx + yy) / 12) << "\"/>\n";
  const double mu = b.friction ? Eval(*b.friction, v) : Eval(d.ground->friction, v);
  const double depth_m = std::min(b.contact_depth ? Eval(*b.contact_depth, v) : 0.0,
                                  0.9 * (sphere ? size[0] / 2 : size[2]));
  if (sphere)  // the contact depth shrinks it about its centre (a box shrinks from below)
    out << in << "<geom type=\"sphere\" size=\"" << Num(size[0] / 2 - depth_m) << "\" friction=\"";
  else
    out << in << "<geom type=\"box\" size=\"" << Num(size[0] / 2) << " " << Num(size[1] / 2) << " "
        << Num((size[2] - depth_m) / 2) << "\" pos=\"0 0 " << Num(depth_m / 2) << "\" friction=\"";
  out << Num(std::isinf(mu) ? 1e3 : mu) << " 0.005 0.0001\" contype=\"1\" conaffinity=\"0\" "
      << "solref=\"0.005 1\" mass=\"0\"/>\n";
  for (auto [it, end] = t.children.equal_range(i); it != end; ++it)
    if (absl::Status s = Body(it->second, depth + 1); !s.ok()) return s;
  out << pad << "</body>\n";
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<std::string> ToMjcf(const robots::RobotDescriptor& d, const ParamValues& v,
                                   double timestep_s) {
  if (d.model != "generic" || d.bodies.empty() || !d.ground)
    return absl::InvalidArgumentError(
        d.source + ": a MuJoCo build needs model: generic, bodies and ground");
  auto tree = MakeTree(d, v);
  if (!tree.ok()) return tree.status();
  const double h = timestep_s > 0 ? timestep_s : v("simulation.timestep_s");
  Writer w{d, v, *tree, {}};
  // Angles in radians, as the descriptor's: MJCF's default unit is the degree (stops, refs).
  w.out << "<mujoco model=\"" << d.name << "\">\n"
        << "  <compiler angle=\"radian\"/>\n"
        << "  <option timestep=\"" << Num(h) << "\" integrator=\"implicit\" cone=\"elliptic\" impratio=\"10\" gravity=\"0 0 "
        << Num(-v("simulation.gravity_m_per_s2")) << "\"/>\n"
        << "  <worldbody>\n"
        << "    <geom name=\"ground\" type=\"plane\" size=\"0 0 1\" friction=\"0 0 0\" "
        << "contype=\"0\" conaffinity=\"1\"/>\n";
  for (size_t i = 0; i < d.bodies.size(); ++i)
    if (tree->parent[i] < 0)
      if (absl::Status s = w.Body(static_cast<int>(i), 0); !s.ok()) return s;
  w.out << "  </worldbody>\n  <actuator>\n";
  for (const robots::Actuator& a : d.actuators) {
    if (a.type != "servo")
      return absl::InvalidArgumentError(absl::StrCat(
          a.mark.ToString(), ": the MuJoCo build drives servos only, not ", a.type, " ", a.name));
    const double torque = Eval(a.max_torque, v);
    if (a.kp) {  // PD: a torque motor, its torque set each step (mujoco_world.cc)
      if (!(torque > 0))
        return absl::InvalidArgumentError(
            absl::StrCat(a.mark.ToString(), ": servo ", a.name, " needs max_torque > 0"));
      w.out << "    <motor name=\"" << a.name << "\" joint=\"" << a.joint
            << "\" ctrllimited=\"true\" ctrlrange=\"" << Num(-torque) << " " << Num(torque) << "\"/>\n";
      continue;
    }
    const double speed = Eval(a.max_speed, v);
    if (!(torque > 0 && speed > 0))
      return absl::InvalidArgumentError(absl::StrCat(a.mark.ToString(), ": servo ", a.name,
                                                     " needs max_torque > 0 and max_speed > 0"));
    w.out << "    <velocity name=\"" << a.name << "\" joint=\"" << a.joint << "\" kv=\""
          << Num(torque / (0.5 * speed)) << "\" forcelimited=\"true\" forcerange=\""
          << Num(-torque) << " " << Num(torque) << "\"/>\n";
  }
  w.out << "  </actuator>\n</mujoco>\n";
  return w.out.str();
}

}  // namespace gaitforge::mujoco
