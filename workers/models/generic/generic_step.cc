// GenericWorld's stepping and sensing (generic_world.h).
#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "workers/models/generic/generic_world.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {

void GenericWorld::ApplyJointTorques() {
  for (size_t i = 0; i < joints_.size(); ++i) {
    const Spring& s = springs_[i];
    if (s.k == 0 && s.c == 0) continue;
    const double angle = dJointGetHingeAngle(joints_[i]);
    const double rate = dJointGetHingeAngleRate(joints_[i]);
    dJointAddHingeTorque(joints_[i], -s.k * (angle - s.rest) - s.c * rate);
  }
}

void GenericWorld::ApplyEffects() {
  if (tether_force_ > 0 || tether_stiffness_ > 0) {
    const double travel = std::max(0.0, dBodyGetPosition(bodies_[0])[0] - start_[0][0]);
    dBodyAddForce(bodies_[0], -(tether_force_ + tether_stiffness_ * travel), 0, 0);
  }
  if (drag_ > 0) {
    for (dBodyID b : bodies_) {
      const dReal* v = dBodyGetLinearVel(b);
      dBodyAddForce(b, -drag_ * v[0], -drag_ * v[1], -drag_ * v[2]);
    }
  }
}

void GenericWorld::ApplyServos(const std::vector<double>& commands) {
  for (size_t i = 0; i < servos_.size(); ++i) {
    Servo& s = servos_[i];
    const double target = i < commands.size() ? commands[i] : 0.0;
    // Exact for a command held over the step: c <- t + (c - t) exp(-h / lag).
    s.command = s.started ? target + (s.command - target) * s.lag_keep : target;
    s.started = true;
    const double angle = dJointGetHingeAngle(joints_[s.joint]);
    const double speed = std::clamp(s.gain * (s.command - angle), -s.max_speed, s.max_speed);
    dJointSetHingeParam(joints_[s.joint], dParamVel, speed);
  }
}

void GenericWorld::AddGroundContacts() {
  ground_contacts_ = 0;
  constexpr int kMax = 8;
  for (size_t i = 0; i < geoms_.size(); ++i) {
    // The plane z = 0, without a geom: a box corner below it is a contact point.
    const dReal* p = dBodyGetPosition(bodies_[i]);
    const dReal* r = dBodyGetRotation(bodies_[i]);
    dVector3 len;
    dGeomBoxGetLengths(geoms_[i], len);
    dContactGeom hits[kMax];
    int n = 0;
    for (int corner = 0; corner < 8 && n < kMax; ++corner) {
      const double lx = (corner & 1 ? 0.5 : -0.5) * len[0];
      const double ly = (corner & 2 ? 0.5 : -0.5) * len[1];
      const double lz = (corner & 4 ? 0.5 : -0.5) * len[2];
      const double z = p[2] + r[8] * lx + r[9] * ly + r[10] * lz;
      if (z > 0) continue;
      dContactGeom& g = hits[n++];
      g.pos[0] = p[0] + r[0] * lx + r[1] * ly + r[2] * lz;
      g.pos[1] = p[1] + r[4] * lx + r[5] * ly + r[6] * lz;
      g.pos[2] = z;
      g.normal[0] = 0;
      g.normal[1] = 0;
      g.normal[2] = 1;
      g.depth = -z;
    }
    int deepest = 0;
    for (int k = 1; k < n; ++k)
      if (hits[k].depth > hits[deepest].depth) deepest = k;
    for (int k = 0; k < n; ++k) {
      dContact c{};
      c.geom = hits[k];
      c.surface.mode = dContactSoftERP | dContactSoftCFM;
      c.surface.soft_erp = contact_erp_;
      c.surface.soft_cfm = contact_cfm_;
      // Friction acts at the deepest corner only, the other corners carry normal force:
      // four corners of a flat box would give eight friction rows for three in-plane
      // freedoms, and ODE's LCP failed on them ("s <= 0") in about 1 gait in 50. The cost:
      // no friction torque about z from a box's footprint (docs/robots.md).
      // A direction-dependent coefficient replaces the ground's own when it is set (> 0).
      const double vx = dBodyGetLinearVel(bodies_[i])[0];
      const double directed = vx >= 0 ? friction_forward_ : friction_backward_;
      if (k != deepest) {
        c.surface.mu = 0;
      } else if (directed > 0) {
        c.surface.mode |= dContactApprox1;
        c.surface.mu = directed;
      } else if (std::isinf(friction_)) {
        c.surface.mu = dInfinity;
      } else {
        c.surface.mode |= dContactApprox1;
        c.surface.mu = friction_;
      }
      dJointID j = dJointCreateContact(world_.world(), world_.contacts(), &c);
      dJointAttach(j, bodies_[i], nullptr);
    }
    ground_contacts_ += n;
  }
}

sim::SimOutcome GenericWorld::CheckState() {
  for (size_t i = 0; i < bodies_.size(); ++i) {
    const dReal* p = dBodyGetPosition(bodies_[i]);
    const dReal* v = dBodyGetLinearVel(bodies_[i]);
    const std::string& name = d_.bodies[i].name;
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(p[k]) || !std::isfinite(v[k]))
        return sim::SimOutcome::Failed(absl::StrCat("NaN in body ", name, " at t = ", time(), " s"));
    }
    const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (speed > max_speed_)
      return sim::SimOutcome::Failed(absl::StrCat("body ", name, " moves at ", speed,
                                                  " m/s (> simulation.max_speed_m_per_s) at t = ",
                                                  time(), " s"));
    const double dx = p[0] - start_[i][0], dy = p[1] - start_[i][1], dz = p[2] - start_[i][2];
    if (std::sqrt(dx * dx + dy * dy + dz * dz) > max_excursion_)
      return sim::SimOutcome::Failed(absl::StrCat(
          "body ", name, " is farther than simulation.max_excursion_m from its start at t = ",
          time(), " s"));
  }
  return sim::SimOutcome::Ok();
}

sim::SimOutcome GenericWorld::Step(const std::vector<double>& commands) {
  ApplyJointTorques();
  ApplyEffects();
  ApplyServos(commands);
  AddGroundContacts();
  try {
    world_.Step(h_);
  } catch (const sim::OdeError& e) {
    return sim::SimOutcome::Failed(absl::StrCat("ODE: ", e.what(), " at t = ", time(), " s"));
  }
  ++steps_;
  return CheckState();
}

std::array<double, 3> GenericWorld::CentreOfMass() const {
  std::array<double, 3> c{};
  double total = 0;
  for (size_t i = 0; i < bodies_.size(); ++i) {
    const dReal* p = dBodyGetPosition(bodies_[i]);
    for (int k = 0; k < 3; ++k) c[k] += masses_[i] * p[k];
    total += masses_[i];
  }
  for (double& x : c) x /= total;
  return c;
}

double GenericWorld::JointAngle(int joint) const { return dJointGetHingeAngle(joints_[joint]); }

absl::StatusOr<double> GenericWorld::Channel(const std::string& name) const {
  const size_t dot = name.rfind('.');
  const std::string base = name.substr(0, dot), field = dot == std::string::npos ? "" : name.substr(dot + 1);
  if (field == "angle") {
    for (size_t i = 0; i < d_.joints.size(); ++i)
      if (d_.joints[i].name == base) return JointAngle(static_cast<int>(i));
  }
  for (const Marker& m : markers_) {
    if (m.name != base || (field != "x" && field != "y" && field != "z")) continue;
    dVector3 out;
    dBodyGetRelPointPos(bodies_[m.body], m.offset[0], m.offset[1], m.offset[2], out);
    return out[field[0] - 'x'];
  }
  return absl::NotFoundError(absl::StrCat(d_.name, " has no channel ", name));
}

}  // namespace gaitforge::generic
