#include "workers/models/generic/generic_world.h"
#include "workers/models/generic/param_eval.h"

#include <cmath>
#include <sstream>
#include <tuple>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "workers/effects/effects.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

// The divergence limits and timing every generic robot gives as parameters.
constexpr const char* kRequired[] = {"simulation.timestep_s", "simulation.gravity_m_per_s2",
                                     "simulation.settle_cycles", "simulation.measured_cycles",
                                     "simulation.max_speed_m_per_s", "simulation.max_excursion_m"};

}  // namespace

ParamValues::ParamValues(const robots::RobotDescriptor& d) : d_(&d) {
  for (const auto& p : d.parameters) values_.push_back(p.value);
}

absl::Status ParamValues::Set(const std::string& name, double value) {
  const std::vector<double> before = values_;
  const std::map<std::string, double> effects_before = effects_;
  if (const robots::Parameter* p = d_->FindParameter(name)) {
    if (std::string bad = p->Check(value); !bad.empty()) return absl::InvalidArgumentError(bad);
    values_[p - d_->parameters.data()] = value;
  } else if (const robots::Scale* scale = d_->FindScale(name)) {
    if (auto s = SetScale(*scale, value); !s.ok()) return s;
  } else if (const auto* e = effects::BuilderParam(name, *d_)) {
    if (!(value >= e->lo && value <= e->hi))
      return absl::InvalidArgumentError(absl::StrCat(name, " = ", value, " ", e->unit,
                                                     " is outside [", e->lo, ", ", e->hi, "]"));
    effects_[name] = value;
    return absl::OkStatus();
  } else {
    std::vector<std::string> known;
    for (const auto& p : d_->parameters) known.push_back(p.name);
    for (const auto& sc : d_->scales) known.push_back(sc.name);
    return absl::NotFoundError(absl::StrCat(d_->name, " has no parameter ", name, "; nearest: ",
                                            absl::StrJoin(robots::Nearest(name, known), ", ")));
  }
  absl::Status rel = d_->CheckRelations([this](const std::string& n) { return (*this)(n); });
  if (!rel.ok()) {
    values_ = before;
    effects_ = effects_before;
    return absl::InvalidArgumentError(absl::StrCat("after ", name, " = ", value, ": ", rel.message()));
  }
  return absl::OkStatus();
}

absl::Status ParamValues::SetScale(const robots::Scale& scale, double factor) {
  if (!std::isfinite(factor) || !(factor > 0))
    return absl::InvalidArgumentError(
        absl::StrCat(scale.name, " = ", factor, " must be a positive finite factor"));
  std::vector<double> next = values_;
  for (const std::string& field : scale.multiplies) {
    const robots::Parameter* p = d_->FindParameter(field);
    const size_t i = p - d_->parameters.data();
    next[i] = values_[i] * factor;
    if (std::string bad = p->Check(next[i]); !bad.empty())
      return absl::InvalidArgumentError(absl::StrCat(scale.name, " = ", factor, " makes ", bad));
  }
  values_ = next;
  return absl::OkStatus();
}

double ParamValues::operator()(const std::string& name) const {
  for (size_t i = 0; i < d_->parameters.size(); ++i)
    if (d_->parameters[i].name == name) return values_[i];
  throw std::out_of_range(absl::StrCat(d_->name, " has no parameter ", name));
}

namespace {

// A creeping contact at its lower edge (the catalog's nominal) is the model's own ground,
// which sticks: no slip at all, so that the robot is as it is bit for bit.
double CreepSlip(const ParamValues& v) {
  const double slip = v.Effect("effect.contact_slip_m_per_n_s");
  return slip > effects::FindEffect("contact.creep")->params[0].nominal ? slip : 0;
}

}  // namespace

BuilderEffects::BuilderEffects(const ParamValues& v)
    : tether_force(v.Effect("effect.tether_force_n")),
      tether_stiffness(v.Effect("effect.tether_stiffness_n_per_m")),
      drag(v.Effect("effect.drag_n_s_per_m")),
      friction_forward(v.Effect("effect.friction_forward")),
      friction_backward(v.Effect("effect.friction_backward")),
      contact_slip(CreepSlip(v)),
      slope(v.Effect("effect.slope_rad")),
      actuator_lag(v.Effect("effect.actuator_lag_s")),
      servo_deadband(v.Effect("effect.servo_deadband_rad")),
      piston_deadband(v.Effect("effect.actuator_deadband_n")),
      spring_softening(v.Effect("effect.spring_softening")),
      lump_compliance(v.Effect("effect.lump_compliance_per_mpa")),
      joint_softening(v.Effect("effect.joint_softening_per_rad")),
      joint_damping_growth(v.Effect("effect.joint_damping_growth_per_rad2")),
      joint_stiffening(v.Effect("effect.joint_stiffening_s_per_rad")) {}

double ParamValues::Effect(const std::string& name) const {
  // A robot may declare an effect's parameter itself, with its own allowed range.
  if (d_->FindParameter(name) != nullptr) return (*this)(name);
  auto it = effects_.find(name);
  return it == effects_.end() ? 0.0 : it->second;
}

GenericWorld::GenericWorld(const robots::RobotDescriptor& d, const ParamValues& v, double timestep_s)
    : d_(d), h_(timestep_s), fx_(v) {}

absl::StatusOr<std::unique_ptr<GenericWorld>> GenericWorld::Build(
    const robots::RobotDescriptor& d, const ParamValues& v, double timestep_s) {
  if (d.bodies.empty())
    return absl::InvalidArgumentError(
        absl::StrCat(d.source, ": the generic builder needs at least one body"));
  for (const char* name : kRequired)
    if (d.FindParameter(name) == nullptr)
      return absl::InvalidArgumentError(
          absl::StrCat(d.source, ": a generic robot needs the parameter ", name));
  if (!d.plane.empty() && d.ground && d.ground->friction_load == "body")
    return absl::InvalidArgumentError(
        d.source + ": ground.friction_load: body is not offered for a planar robot");
  const double h = timestep_s > 0 ? timestep_s : v("simulation.timestep_s");
  std::unique_ptr<GenericWorld> w(new GenericWorld(d, v, h));
  // A ground slope s (effect.slope_rad, + uphill along +x) tilts gravity about y.
  const double g = v("simulation.gravity_m_per_s2"), slope = w->fx_.slope;
  dWorldSetGravity(w->world_.world(), -g * std::sin(slope), 0, -g * std::cos(slope));
  // Rigid rows: drift correction and softness, the robot's simulation.solver_erp and
  // simulation.solver_cfm when it gives them (a small positive CFM keeps the solver's
  // matrix regular where rows over-constrain a body).
  const auto optional = [&](const char* name, double fallback) {
    return d.FindParameter(name) ? v(name) : fallback;
  };
  dWorldSetERP(w->world_.world(), optional("simulation.solver_erp", 0.2));
  dWorldSetCFM(w->world_.world(), optional("simulation.solver_cfm", 1e-6));
  if (absl::Status s = w->BuildBodies(v); !s.ok()) return s;
  if (absl::Status s = w->BuildJoints(v); !s.ok()) return s;
  if (absl::Status s = w->BuildActuators(v); !s.ok()) return s;
  w->BuildMarkers(v);
  if (absl::Status s = w->BuildLearned(v); !s.ok()) return s;
  // Without ground (an arm on a mount, a test rig in free space) nothing touches z = 0.
  if (d.ground) {
    w->friction_ = Eval(d.ground->friction, v);
    w->contact_erp_ = Eval(d.ground->erp, v);
    w->contact_cfm_ = Eval(d.ground->cfm, v);
  }
  for (size_t i = 0; i < d.bodies.size(); ++i) {
    const robots::Body& b = d.bodies[i];
    const double mu = b.friction ? Eval(*b.friction, v) : w->friction_;
    const double depth = b.contact_depth ? Eval(*b.contact_depth, v) : 0.0;
    if (!(mu >= 0 && depth >= 0))
      return absl::InvalidArgumentError(absl::StrCat(
          b.mark.ToString(), ": body ", b.name, "'s friction and contact_depth must be >= 0"));
    w->body_friction_.insert(w->body_friction_.end(), w->built_[i].parts, mu);
    w->contact_depth_.insert(w->contact_depth_.end(), w->built_[i].parts, depth);
  }
  const size_t n = w->bodies_.size();
  w->body_load_ = d.ground && d.ground->friction_load == "body";
  w->load_.assign(n, 0.0);
  w->contact_feedback_.resize(n * kMaxContacts);
  w->contact_count_.assign(n, 0);
  // Bodies that a joint joins (a split body's halves too) overlap there and never touch.
  for (size_t i = 0; i < n && d.self_contact; ++i)
    for (size_t k = i + 1; k < n; ++k)
      if (!dAreConnectedExcluding(w->bodies_[i], w->bodies_[k], dJointTypeContact)) {
        const auto& a = w->sizes_[i];
        const auto& b = w->sizes_[k];
        const double reach = 0.5 * (std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]) +
                                    std::sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]));
        w->contact_pairs_.push_back({static_cast<int>(i), static_cast<int>(k), reach * reach});
      }
  w->max_speed_ = v("simulation.max_speed_m_per_s");
  w->max_excursion_ = v("simulation.max_excursion_m");
  return w;
}

absl::Status GenericWorld::BuildBodies(const ParamValues& v) {
  for (size_t i = 0; i < d_.bodies.size(); ++i)
    if (absl::Status s = BuildBody(static_cast<int>(i), v); !s.ok()) return s;
  return absl::OkStatus();
}

void GenericWorld::CreateBody(const std::string& name, const std::array<double, 3>& size,
                              double mass, const std::array<double, 3>& pos,
                              const dReal* rotation, bool sphere) {
  dBodyID body = dBodyCreate(world_.world());
  dMass m;
  if (sphere)
    dMassSetSphereTotal(&m, mass, size[0] / 2);
  else
    dMassSetBoxTotal(&m, mass, size[0], size[1], size[2]);
  dBodySetMass(body, &m);
  dBodySetPosition(body, pos[0], pos[1], pos[2]);
  if (rotation) dBodySetRotation(body, rotation);
  dGeomID geom = sphere ? dCreateSphere(world_.space(), size[0] / 2)
                        : dCreateBox(world_.space(), size[0], size[1], size[2]);
  dGeomSetBody(geom, body);
  radius_.push_back(sphere ? size[0] / 2 : 0.0);
  bodies_.push_back(body);
  geoms_.push_back(geom);
  masses_.push_back(mass);
  sizes_.push_back(size);
  start_.push_back(pos);
  body_names_.push_back(name);
}

absl::Status GenericWorld::BuildJoints(const ParamValues& v) {
  // A split body's halves are joined first (generic_resolution.cc).
  for (size_t i = 0; i < built_.size(); ++i) {
    const Built& b = built_[i];
    if (b.parts != 2) continue;
    const Split& s = splits_[i];
    std::array<double, 3> p1;
    for (int k = 0; k < 3; ++k) p1[k] = b.centre[k] - b.half_x * b.axis[k];
    // The halves: reduced mass m/4, reduced inertia half the half-body's.
    dMass half;
    dBodyGetMass(bodies_[b.first], &half);
    const double i_half = half.I[1 * 4 + 1];
    AddLink(bodies_[b.first], bodies_[b.first + 1], b.centre, b.axis, p1, s.k, s.kappa,
            Damping(s.zeta, s.k, half.mass, half.mass), Damping(s.zeta_bend, s.kappa, i_half, i_half));
  }
  // A joint's body (the half nearest its anchor, if split); none (0) for the world frame.
  auto body = [this](const std::string& name, const std::array<double, 3>& anchor) -> dBodyID {
    const int i = BodyIndex(name);
    return i < 0 ? nullptr : bodies_[NearPart(i, anchor)];
  };
  for (const robots::Joint& j : d_.joints) {
    joint_link_.push_back(-1);
    const auto anchor = j.type == "fixed" ? std::array<double, 3>{} : Eval(j.anchor, v);
    if (j.type == "spring_link") {
      joint_link_.back() = static_cast<int>(links_.size());
      if (absl::Status s = BuildSpringLink(j, v); !s.ok()) return s;
      joints_.push_back(links_.back().bend);
      springs_.push_back({});
      continue;
    }
    if (j.type == "fixed") {
      dJointID weld = dJointCreateFixed(world_.world(), nullptr);
      dJointAttach(weld, body(j.body1, anchor), body(j.body2, anchor));
      dJointSetFixed(weld);
      joints_.push_back(weld);
      springs_.push_back({});
      continue;
    }
    if (j.type == "universal") {
      const dJointID u = BuildUniversal(j, body(j.body1, anchor), body(j.body2, anchor), v);
      joints_.push_back(u);
      Spring s = SpringOf(j, v);
      AddUniversalDamper(u, s);
      s.c = s.c2 = 0;  // the dampers are rows; the springs stay torques
      springs_.push_back(s);
      continue;
    }
    dJointID hinge = dJointCreateHinge(world_.world(), nullptr);
    dJointAttach(hinge, body(j.body1, anchor), body(j.body2, anchor));
    dJointSetHingeAnchor(hinge, anchor[0], anchor[1], anchor[2]);
    dJointSetHingeAxis(hinge, j.axis[0], j.axis[1], j.axis[2]);
    if (j.lo) {
      const double lo = Eval(*j.lo, v), hi = Eval(*j.hi, v);
      if (!(lo <= 0 && 0 <= hi))
        return absl::InvalidArgumentError(absl::StrCat(
            j.mark.ToString(), ": joint ", j.name, "'s stops [", lo, ", ", hi,
            "] rad must hold its starting angle 0"));
      dJointSetHingeParam(hinge, dParamHiStop, hi);
      dJointSetHingeParam(hinge, dParamLoStop, lo);
    }
    if (j.friction) {
      // Coulomb friction as the hinge's motor row held at zero speed with at most the
      // friction torque: it holds the joint against less and opposes turning with that much.
      const double friction = Eval(*j.friction, v);
      if (!(friction >= 0))
        return absl::InvalidArgumentError(absl::StrCat(
            j.mark.ToString(), ": joint ", j.name, "'s friction ", friction, " N m must be >= 0"));
      dJointSetHingeParam(hinge, dParamVel, 0);
      dJointSetHingeParam(hinge, dParamFMax, friction);
    }
    joints_.push_back(hinge);
    springs_.push_back(SpringOf(j, v));
  }
  return absl::OkStatus();
}

dJointID GenericWorld::BuildUniversal(const robots::Joint& j, dBodyID b1, dBodyID b2,
                                      const ParamValues& v) {
  dJointID u = dJointCreateUniversal(world_.world(), nullptr);
  dJointAttach(u, b1, b2);
  const auto anchor = Eval(j.anchor, v);
  dJointSetUniversalAnchor(u, anchor[0], anchor[1], anchor[2]);
  dJointSetUniversalAxis1(u, j.axis[0], j.axis[1], j.axis[2]);
  dJointSetUniversalAxis2(u, j.axis2[0], j.axis2[1], j.axis2[2]);
  return u;
}

// A universal joint's dampers as two soft velocity rows of an angular motor on its axes
// (ode-notes.md, "Springs and dampers": a row with target speed 0 and CFM 1/c is the
// implicit damper f = -c w_{n+1}). Explicit damping torques need c h small against the
// lighter body's inertia about the axis, which a chain of light disks on long links (paper
// 004's arm, with the stiffness and damping a GA searches) does not give; implicit rows are
// stable for any c. The axes follow the joint's (UpdateUniversalDampers, every step).
void GenericWorld::AddUniversalDamper(dJointID u, const Spring& s) {
  const double c1 = s.c, c2 = s.c2;
  if (c1 <= 0 && c2 <= 0) return;
  dJointID m = dJointCreateAMotor(world_.world(), nullptr);
  dJointAttach(m, dJointGetBody(u, 0), dJointGetBody(u, 1));
  dJointSetAMotorMode(m, dAMotorUser);
  dJointSetAMotorNumAxes(m, 2);
  const struct {
    int vel, fmax, cfm;
    double c;
  } axes[2] = {{dParamVel, dParamFMax, dParamCFM, c1}, {dParamVel2, dParamFMax2, dParamCFM2, c2}};
  for (const auto& a : axes) {
    dJointSetAMotorParam(m, a.vel, 0);
    dJointSetAMotorParam(m, a.fmax, a.c > 0 ? dInfinity : 0);
    if (a.c > 0) dJointSetAMotorParam(m, a.cfm, 1 / a.c);
  }
  universal_dampers_.push_back({u, m, c1, c2, s.rest, s.rest2});
  UpdateUniversalDampers();
}

// Every step: the rows' axes follow the joint's, and with effect.joint_damping_growth_per_rad2
// = b each axis damps with c (1 + b psi^2) at its deflection psi.
void GenericWorld::UpdateUniversalDampers() {
  const double b = fx_.joint_damping_growth;
  for (const UniversalDamper& d : universal_dampers_) {
    dVector3 x1, x2;  // world frame
    dJointGetUniversalAxis1(d.joint, x1);
    dJointGetUniversalAxis2(d.joint, x2);
    dJointSetAMotorAxis(d.motor, 0, 0, x1[0], x1[1], x1[2]);
    dJointSetAMotorAxis(d.motor, 1, 0, x2[0], x2[1], x2[2]);
    if (b <= 0) continue;
    const double p1 = UniversalAngle(d.joint, 1) - d.rest1, p2 = UniversalAngle(d.joint, 2) - d.rest2;
    if (d.c1 > 0) dJointSetAMotorParam(d.motor, dParamCFM, 1 / (d.c1 * (1 + b * p1 * p1)));
    if (d.c2 > 0) dJointSetAMotorParam(d.motor, dParamCFM2, 1 / (d.c2 * (1 + b * p2 * p2)));
  }
}

GenericWorld::Spring GenericWorld::SpringOf(const robots::Joint& j, const ParamValues& v) {
  Spring s;
  auto set = [&v](const std::optional<robots::Expr>& e, double& out) {
    if (e) out = Eval(*e, v);
  };
  set(j.stiffness, s.k);
  set(j.damping, s.c);
  set(j.rest, s.rest);
  set(j.stiffness2, s.k2);
  set(j.damping2, s.c2);
  set(j.rest2, s.rest2);
  return s;
}

absl::Status GenericWorld::BuildActuators(const ParamValues& v) {
  actuator_torque_.assign(d_.actuators.size(), 0.0);
  actuator_rate_.assign(d_.actuators.size(), 0.0);
  for (size_t index = 0; index < d_.actuators.size(); ++index) {
    const robots::Actuator& a = d_.actuators[index];
    if (a.type == "piston") {
      if (absl::Status s = BuildPiston(a, static_cast<int>(index), v); !s.ok()) return s;
      continue;
    }
    if (a.type == "tendon") {
      if (absl::Status s = BuildTendon(a, static_cast<int>(index), v); !s.ok()) return s;
      continue;
    }
    Servo s;
    s.actuator = static_cast<int>(index);
    for (size_t i = 0; i < d_.joints.size(); ++i)
      if (d_.joints[i].name == a.joint) s.joint = static_cast<int>(i);
    s.max_torque = Eval(a.max_torque, v);
    const double lag = Eval(a.lag_s, v);
    s.pd = a.kp.has_value();
    if (s.pd) {
      s.kp = Eval(*a.kp, v);
      s.kd = Eval(*a.kd, v);
      if (!(s.kp > 0 && s.kd >= 0 && s.max_torque > 0 && lag >= 0))
        return absl::InvalidArgumentError(absl::StrCat(
            a.mark.ToString(), ": PD servo ", a.name,
            " needs kp > 0, kd >= 0, max_torque > 0 and lag_s >= 0"));
    } else {
      s.gain = Eval(a.gain, v);
      s.max_speed = Eval(a.max_speed, v);
      if (d_.joints[s.joint].friction)
        return absl::InvalidArgumentError(absl::StrCat(
            a.mark.ToString(), ": servo ", a.name, " drives joint ", a.joint,
            " with a speed command, whose motor cannot also be the joint's friction: make it a "
            "PD servo (kp, kd) or give the joint no friction"));
      if (!(s.gain > 0 && s.max_speed > 0 && s.max_torque >= 0 && lag >= 0))
        return absl::InvalidArgumentError(absl::StrCat(
            a.mark.ToString(), ": servo ", a.name,
            " needs gain > 0, max_speed > 0, max_torque >= 0 and lag_s >= 0"));
      dJointSetHingeParam(joints_[s.joint], dParamFMax, s.max_torque);
    }
    s.lag_keep = lag > 0 ? std::exp(-h_ / lag) : 0;
    s.extra_keep = fx_.actuator_lag > 0 ? std::exp(-h_ / fx_.actuator_lag) : 0;
    // The joint's reaction, read after each step for the torque the servo gave.
    dJointSetFeedback(joints_[s.joint], &feedback_.emplace_back());
    servos_.push_back(s);
  }
  return absl::OkStatus();
}

void GenericWorld::BuildMarkers(const ParamValues& v) {
  for (const robots::Sensor& s : d_.sensors) {
    if (s.kind != "marker" || s.bodies.empty()) continue;
    for (size_t i = 0; i < s.names.size(); ++i) {
      Marker m;
      m.name = s.names[i];
      std::tie(m.body, m.offset) = Locate(BodyIndex(s.bodies[i]),
                                          s.offset ? Eval(*s.offset, v) : std::array<double, 3>{});
      markers_.push_back(m);
    }
  }
}

}  // namespace gaitforge::generic
