// GenericWorld's stepping and sensing (generic_world.h).
#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "workers/models/generic/generic_world.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {

void GenericWorld::AddUniversalSpring(dJointID j, const Spring& s) {
  // The joint's axes and bodies as the descriptor gives them (ODE's getters undo its own
  // swap of a joint held by the world); +t on the first body and -t on the second, the
  // sense of a hinge's torque, with angles and rates in the sense of the first body's turn
  // relative to the second.
  dVector3 x1, x2;
  dJointGetUniversalAxis1(j, x1);
  dJointGetUniversalAxis2(j, x2);
  const dBodyID b1 = dJointGetBody(j, 0), b2 = dJointGetBody(j, 1);
  dReal w[3] = {0, 0, 0};
  if (b1) for (int k = 0; k < 3; ++k) w[k] += dBodyGetAngularVel(b1)[k];
  if (b2) for (int k = 0; k < 3; ++k) w[k] -= dBodyGetAngularVel(b2)[k];
  const double r1 = x1[0] * w[0] + x1[1] * w[1] + x1[2] * w[2];
  const double r2 = x2[0] * w[0] + x2[1] * w[1] + x2[2] * w[2];
  const double t1 = -SpringTorque(s.k, UniversalAngle(j, 1) - s.rest, r1) - s.c * r1;
  const double t2 = -SpringTorque(s.k2, UniversalAngle(j, 2) - s.rest2, r2) - s.c2 * r2;
  const dReal t[3] = {t1 * x1[0] + t2 * x2[0], t1 * x1[1] + t2 * x2[1], t1 * x1[2] + t2 * x2[2]};
  if (b1) dBodyAddTorque(b1, t[0], t[1], t[2]);
  if (b2) dBodyAddTorque(b2, -t[0], -t[1], -t[2]);
}

// k psi, softened with deflection and stiffened with rate by the bending-joint effects.
double GenericWorld::SpringTorque(double k, double psi, double rate) const {
  double t = k * psi;
  if (fx_.joint_softening > 0) t /= std::sqrt(1 + fx_.joint_softening * fx_.joint_softening * psi * psi);
  if (fx_.joint_stiffening > 0) t *= 1 + fx_.joint_stiffening * std::fabs(rate);
  return t;
}

double GenericWorld::UniversalAngle(dJointID j, int axis) {
  // Checked against the bodies' relative turn (AddUniversalSpring's rates): ODE's angle 2
  // has that sense; its angle 1 too, but for a joint held by the world, which ODE stores
  // with its bodies swapped, where angle 1 comes out negated.
  if (axis == 2) return dJointGetUniversalAngle2(j);
  return (dJointGetBody(j, 0) == nullptr ? -1.0 : 1.0) * dJointGetUniversalAngle1(j);
}

void GenericWorld::ApplyJointTorques() {
  for (size_t i = 0; i < joints_.size(); ++i) {
    const Spring& s = springs_[i];
    const dJointID j = joints_[i];
    if (dJointGetType(j) == dJointTypeUniversal) {
      if (s.k == 0 && s.c == 0 && s.k2 == 0 && s.c2 == 0) continue;
      AddUniversalSpring(j, s);
      continue;
    }
    if (s.k == 0 && s.c == 0) continue;  // a fixed joint's spring is {}
    const double angle = dJointGetHingeAngle(j);
    const double rate = dJointGetHingeAngleRate(j);
    dJointAddHingeTorque(j, -s.k * (angle - s.rest) - s.c * rate);
  }
  UpdateUniversalDampers();
}

void GenericWorld::ApplyEffects() {
  // Forces on a body act at its centre; a split body's halves share them.
  const Built& first = built_[0];
  if (fx_.tether_force > 0 || fx_.tether_stiffness > 0) {
    auto x = [&](const dReal* p0, const dReal* p1) { return p1 ? (p0[0] + p1[0]) / 2 : p0[0]; };
    const bool split = first.parts == 2;
    const double now = x(dBodyGetPosition(bodies_[0]), split ? dBodyGetPosition(bodies_[1]) : nullptr);
    const double start = x(start_[0].data(), split ? start_[1].data() : nullptr);
    const double travel = std::max(0.0, now - start);
    const double pull = -(fx_.tether_force + fx_.tether_stiffness * travel) / first.parts;
    for (int part = 0; part < first.parts; ++part) dBodyAddForce(bodies_[part], pull, 0, 0);
  }
  if (fx_.drag > 0) {
    for (const Built& b : built_)
      for (int part = 0; part < b.parts; ++part) {
        const dBodyID body = bodies_[b.first + part];
        const double c = fx_.drag / b.parts;
        const dReal* v = dBodyGetLinearVel(body);
        dBodyAddForce(body, -c * v[0], -c * v[1], -c * v[2]);
      }
  }
  if (fx_.spring_softening > 0) SoftenLinks();
}

void GenericWorld::ApplyServos(const std::vector<double>& commands) {
  for (size_t i = 0; i < servos_.size(); ++i) {
    Servo& s = servos_[i];
    const double target = static_cast<size_t>(s.actuator) < commands.size() ? commands[s.actuator] : 0.0;
    // Exact for a command held over the step: c <- t + (c - t) exp(-h / lag). The effect's
    // lag (effect.actuator_lag_s) comes first, then the servo's own.
    s.extra = s.started ? target + (s.extra - target) * s.extra_keep : target;
    s.command = s.started ? s.extra + (s.command - s.extra) * s.lag_keep : s.extra;
    s.started = true;
    const double angle = dJointGetHingeAngle(joints_[s.joint]);
    // A deadband (effect.servo_deadband_rad): inside it the servo does not drive; its
    // geared motor holds (speed 0 up to max_torque).
    const double error = s.command - angle;
    const double drive = std::fabs(error) <= fx_.servo_deadband ? 0.0 : error;
    if (s.pd) {  // an explicit torque (stable while h kd / I and h^2 kp / I stay small)
      const double rate = dJointGetHingeAngleRate(joints_[s.joint]);
      // A controller's feed-forward torque follows the set-points (DescriptorOrder).
      const size_t ff = d_.actuators.size() + static_cast<size_t>(s.actuator);
      const double feed = ff < commands.size() ? commands[ff] : 0.0;
      s.torque = std::clamp(s.kp * drive - s.kd * rate + feed, -s.max_torque, s.max_torque);
      dJointAddHingeTorque(joints_[s.joint], s.torque);
      continue;
    }
    const double speed = std::clamp(s.gain * drive, -s.max_speed, s.max_speed);
    dJointSetHingeParam(joints_[s.joint], dParamVel, speed);
  }
}

void GenericWorld::AddGroundContacts() {
  ground_contacts_ = 0;
  constexpr int kMax = kMaxContacts;
  for (size_t i = 0; i < geoms_.size(); ++i) {
    // The plane z = 0, without a geom: a box corner below it is a contact point.
    const dReal* p = dBodyGetPosition(bodies_[i]);
    const dReal* r = dBodyGetRotation(bodies_[i]);
    dVector3 len;
    dContactGeom hits[kMax];
    int n = 0;
    if (radius_[i] > 0) {  // a sphere touches at its lowest point
      const double z = p[2] - radius_[i];
      if (z <= -contact_depth_[i]) {
        dContactGeom& g = hits[n++];
        g.pos[0] = p[0];
        g.pos[1] = p[1];
        g.pos[2] = z;
        g.normal[0] = g.normal[1] = 0;
        g.normal[2] = 1;
        g.depth = -z - contact_depth_[i];
      }
    } else {
      dGeomBoxGetLengths(geoms_[i], len);
    }
    for (int corner = 0; corner < 8 && n < kMax && radius_[i] == 0; ++corner) {
      const double lx = (corner & 1 ? 0.5 : -0.5) * len[0];
      const double ly = (corner & 2 ? 0.5 : -0.5) * len[1];
      const double lz = (corner & 4 ? 0.5 : -0.5) * len[2];
      const double z = p[2] + r[8] * lx + r[9] * ly + r[10] * lz;
      // A body with a contact depth d touches only once a corner is deeper than d: it
      // rests d deep (the allowed overlap), pushed back only by what lies beyond.
      if (z > -contact_depth_[i]) continue;
      dContactGeom& g = hits[n++];
      g.pos[0] = p[0] + r[0] * lx + r[1] * ly + r[2] * lz;
      g.pos[1] = p[1] + r[4] * lx + r[5] * ly + r[6] * lz;
      g.pos[2] = z;
      g.normal[0] = 0;
      g.normal[1] = 0;
      g.normal[2] = 1;
      g.depth = -z - contact_depth_[i];
    }
    // The deepest corner: the lowest.
    int deepest = 0;
    for (int k = 1; k < n; ++k)
      if (hits[k].pos[2] < hits[deepest].pos[2]) deepest = k;
    for (int k = 0; k < n; ++k) {
      dContact c{};
      c.geom = hits[k];
      c.surface.mode = dContactSoftERP | dContactSoftCFM;
      c.surface.soft_erp = contact_erp_;
      c.surface.soft_cfm = contact_cfm_;
      if (fx_.contact_slip > 0) {  // a creeping contact: ODE's force-dependent slip
        c.surface.mode |= dContactSlip1 | dContactSlip2;
        c.surface.slip1 = c.surface.slip2 = fx_.contact_slip;
      }
      // Friction acts at the deepest corner only, the other corners carry normal force:
      // four corners of a flat box would give eight friction rows for three in-plane
      // freedoms, and ODE's LCP failed on them ("s <= 0") in about 1 gait in 50. The cost:
      // no friction torque about z from a box's footprint (docs/robots.md).
      // A direction-dependent coefficient replaces the ground's own when it is set (> 0).
      const double vx = dBodyGetLinearVel(bodies_[i])[0];
      const double directed = vx >= 0 ? fx_.friction_forward : fx_.friction_backward;
      const double mu = directed > 0 ? directed : body_friction_[i];
      if (k != deepest) {
        c.surface.mu = 0;
      } else if (std::isinf(mu)) {
        c.surface.mu = dInfinity;
      } else if (body_load_) {
        // ODE's constant-bound friction: the bound is a force, mu times the box's load.
        c.surface.mu = mu * load_[i];
      } else {
        c.surface.mode |= dContactApprox1;
        c.surface.mu = mu;
      }
      dJointID j = dJointCreateContact(world_.world(), world_.contacts(), &c);
      dJointAttach(j, bodies_[i], nullptr);
      if (body_load_) dJointSetFeedback(j, &contact_feedback_[i * kMaxContacts + k]);
    }
    contact_count_[i] = n;
    ground_contacts_ += n;
  }
}

sim::SimOutcome GenericWorld::CheckState() {
  for (size_t i = 0; i < bodies_.size(); ++i) {
    const dReal* p = dBodyGetPosition(bodies_[i]);
    const dReal* v = dBodyGetLinearVel(bodies_[i]);
    const dReal* w = dBodyGetAngularVel(bodies_[i]);
    const std::string& name = body_names_[i];
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(p[k]) || !std::isfinite(v[k]) || !std::isfinite(w[k]))
        return sim::SimOutcome::Failed(absl::StrCat("diverged: NaN in body ", name, " at t = ", time(), " s"));
    }
    const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (speed > max_speed_)
      return sim::SimOutcome::Failed(absl::StrCat("diverged: body ", name, " moves at ", speed,
                                                  " m/s (> simulation.max_speed_m_per_s) at t = ",
                                                  time(), " s"));
    // Spinning so fast that the ends of its length along x would pass the speed limit.
    const double spin = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    if (spin > 2 * max_speed_ / sizes_[i][0])
      return sim::SimOutcome::Failed(absl::StrCat(
          "diverged: body ", name, " spins at ", spin, " rad/s (> 2 simulation.max_speed_m_per_s / its x "
          "length) at t = ", time(), " s"));
    const double dx = p[0] - start_[i][0], dy = p[1] - start_[i][1], dz = p[2] - start_[i][2];
    if (std::sqrt(dx * dx + dy * dy + dz * dz) > max_excursion_)
      return sim::SimOutcome::Failed(absl::StrCat(
          "diverged: body ", name, " is farther than simulation.max_excursion_m from its start at t = ",
          time(), " s"));
  }
  return CheckPistons();
}

sim::SimOutcome GenericWorld::Step(const std::vector<double>& commands) {
  try {
    ApplyLearned();
    ApplyJointTorques();
    ApplyPistons(commands);
    ApplyTendons(commands);
    ApplyEffects();
    ApplyServos(commands);
    if (!d_.ground) {
      ground_contacts_ = -1;  // nothing to touch: not "airborne"
    } else if (d_.plane.empty()) {
      AddGroundContacts();
    } else {
      AddPlanarGroundContacts();
    }
    AddSelfContacts();
    UpdateLinkAngles();
    world_.Step(h_);
  } catch (const sim::OdeError& e) {
    return sim::SimOutcome::Failed(absl::StrCat("ODE: ", e.what(), " at t = ", time(), " s"));
  }
  ++steps_;
  MeasurePistons();
  Observe();
  return CheckState();
}

void GenericWorld::Observe() {
  if (body_load_)
    for (size_t i = 0; i < bodies_.size(); ++i) {
      // The ground's push on the box: the contacts' forces on it along the normal (+z).
      double load = 0;
      for (int k = 0; k < contact_count_[i]; ++k) load += contact_feedback_[i * kMaxContacts + k].f1[2];
      load_[i] = std::max(0.0, load);
    }
  // Tilt: the body's z axis against the world's, split into pitch (about y) and roll.
  const dReal* r = dBodyGetRotation(bodies_[0]);
  const double pitch = std::atan2(r[2], r[10]), roll = std::atan2(r[6], r[10]);
  max_tilt_ = std::max({max_tilt_, std::fabs(pitch), std::fabs(roll)});
  for (size_t i = 0; i < servos_.size(); ++i) {
    if (servos_[i].pd) {  // its own torque, which turns the hinge's angle up
      const Servo& s = servos_[i];
      if (std::fabs(s.torque) >= 0.99 * s.max_torque) ++torque_limited_;
      const double rate = dJointGetHingeAngleRate(joints_[s.joint]);
      servo_energy_ += std::max(0.0, s.torque * rate) * h_;
      actuator_torque_[s.actuator] = s.torque;
      actuator_rate_[s.actuator] = rate;
      continue;
    }
    // The torque about the hinge axis that the joint put on its second body: the reaction's
    // torque about that body's centre less the moment of the reaction's force at the anchor.
    const dJointID j = joints_[servos_[i].joint];
    const dJointFeedback& f = feedback_[i];
    dVector3 anchor, axis;
    dJointGetHingeAnchor2(j, anchor);
    dJointGetHingeAxis(j, axis);
    const dReal* c = dBodyGetPosition(dJointGetBody(j, 1));
    const double rx = anchor[0] - c[0], ry = anchor[1] - c[1], rz = anchor[2] - c[2];
    const double tx = f.t2[0] - (ry * f.f2[2] - rz * f.f2[1]);
    const double ty = f.t2[1] - (rz * f.f2[0] - rx * f.f2[2]);
    const double tz = f.t2[2] - (rx * f.f2[1] - ry * f.f2[0]);
    // Signed: the torque on the second body about the axis, along which the rate is taken.
    const double torque = tx * axis[0] + ty * axis[1] + tz * axis[2];
    if (servos_[i].max_torque > 0 && std::fabs(torque) >= 0.99 * servos_[i].max_torque)
      ++torque_limited_;
    // Its power: the torque on body 2 times body 2's spin about the axis relative to body 1
    // (body 1 takes the opposite torque), computed from the bodies to need no sign rule.
    const dReal* w1 = dBodyGetAngularVel(dJointGetBody(j, 0));
    const dReal* w2 = dBodyGetAngularVel(dJointGetBody(j, 1));
    const double spin = (w2[0] - w1[0]) * axis[0] + (w2[1] - w1[1]) * axis[1] + (w2[2] - w1[2]) * axis[2];
    servo_energy_ += std::max(0.0, torque * spin) * h_;
    actuator_torque_[servos_[i].actuator] = torque;
    actuator_rate_[servos_[i].actuator] = spin;
  }
}

double GenericWorld::total_mass() const {
  double m = 0;
  for (double x : masses_) m += x;
  return m;
}

double GenericWorld::torque_limited_fraction() const {
  const double n = static_cast<double>(steps_) * static_cast<double>(servos_.size());
  return n > 0 ? static_cast<double>(torque_limited_) / n : 0.0;
}

std::array<double, 3> GenericWorld::CentreOfMass() const {
  // Weights relative to the first body's mass: equal bodies weigh exactly 1 each, so their
  // centre is the plain mean of their positions, to the last bit.
  std::array<double, 3> c{};
  double total = 0;
  for (size_t i = 0; i < bodies_.size(); ++i) {
    const dReal* p = dBodyGetPosition(bodies_[i]);
    const double weight = masses_[i] / masses_[0];
    for (int k = 0; k < 3; ++k) c[k] += weight * p[k];
    total += weight;
  }
  for (double& x : c) x /= total;
  return c;
}

std::array<double, 3> GenericWorld::BodyCentre(int body) const {
  const Built& b = built_[body];
  const dReal* p = dBodyGetPosition(bodies_[b.first]);
  if (b.parts == 1) return {p[0], p[1], p[2]};
  const dReal* q = dBodyGetPosition(bodies_[b.first + 1]);
  return {(p[0] + q[0]) / 2, (p[1] + q[1]) / 2, (p[2] + q[2]) / 2};
}

robots::BodyState GenericWorld::StateOf(int body) const {
  const dBodyID b = bodies_[built_[body].first];
  robots::BodyState s;
  s.position = BodyCentre(body);
  const dReal* r = dBodyGetRotation(b);  // 3 x 4, row-major
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) s.rotation[3 * i + k] = r[4 * i + k];
  const dReal* v = dBodyGetLinearVel(b);
  const dReal* w = dBodyGetAngularVel(b);
  for (int k = 0; k < 3; ++k) {
    s.velocity[k] = v[k];
    s.spin[k] = w[k];
  }
  return s;
}

double GenericWorld::JointAngle(int joint, int axis) const {
  if (joint_link_[joint] >= 0) return Bend(links_[joint_link_[joint]]);
  const dJointID j = joints_[joint];
  switch (dJointGetType(j)) {
    case dJointTypeHinge: return dJointGetHingeAngle(j);
    case dJointTypeUniversal: return UniversalAngle(j, axis);
    default: return 0.0;
  }
}

absl::StatusOr<double> GenericWorld::Channel(const std::string& name) const {
  const size_t dot = name.rfind('.');
  const std::string base = name.substr(0, dot), field = dot == std::string::npos ? "" : name.substr(dot + 1);
  for (size_t i = 0; i < d_.joints.size(); ++i) {
    if (d_.joints[i].name != base) continue;
    const std::vector<std::string> fields = d_.joints[i].AngleFields();
    for (size_t a = 0; a < fields.size(); ++a)
      if (fields[a] == field) return JointAngle(static_cast<int>(i), static_cast<int>(a) + 1);
  }
  for (const Marker& m : markers_) {
    if (m.name != base || (field != "x" && field != "y" && field != "z")) continue;
    dVector3 out;
    dBodyGetRelPointPos(bodies_[m.body], m.offset[0], m.offset[1], m.offset[2], out);
    return out[field[0] - 'x'];
  }
  if (auto v = ActuatorChannel(d_, base, field)) return *v;
  return absl::NotFoundError(absl::StrCat(d_.name, " has no channel ", name));
}

}  // namespace gaitforge::generic
