#include "workers/models/caterpillar/caterpillar_sim.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "workers/sim/ode_runtime.h"

namespace gaitforge::caterpillar {
namespace {

// Contact with no friction rows beyond the normal: lump-lump touches and stroke stops.
dContact FrictionlessContact() {
  dContact c{};
  c.surface.mode = dContactMu2;
  c.surface.mu = 0;
  c.surface.mu2 = 0;
  return c;
}

}  // namespace

CaterpillarSim::CaterpillarSim(const CaterpillarParams& params, const BuildOptions& options,
                               double timestep_s)
    : params_(params),
      h_(timestep_s > 0 ? timestep_s : params.simulation.timestep_s),
      world_() {
  const auto& e = params.effects;
  if (e.slope_rad != 0 && options.gravity) {
    // The world frame is the ground's: uphill along +x tilts gravity towards -x.
    const double g = params.simulation.gravity_m_per_s2;
    dWorldSetGravity(world_.world(), -g * std::sin(e.slope_rad), 0, -g * std::cos(e.slope_rad));
  } else {
    dWorldSetGravity(world_.world(), 0, 0,
                     options.gravity ? -params.simulation.gravity_m_per_s2 : 0.0);
  }
  dWorldSetERP(world_.world(), params.simulation.solver_erp);
  dWorldSetCFM(world_.world(), params.simulation.solver_cfm);
  body_ = std::make_unique<CaterpillarBody>(world_.world(), world_.space(), params, options, h_);
  for (int k = 0; k < body_->lump_count(); ++k) start_.push_back(body_->Position(k));
  for (int i = 0; i < body_->body_count(); ++i) {
    const dReal* p = dBodyGetPosition(body_->body(i));
    body_start_.push_back({p[0], p[1], p[2]});
  }
  MeasureLengths();

  if (e.actuator_lag_s != 0 || e.actuator_delay_s != 0) {
    shaped_push_ = true;
    push_.assign(body_->actuators().size(), 0.0);
    if (e.actuator_lag_s != 0) lag_keep_ = std::exp(-h_ / e.actuator_lag_s);
    if (e.actuator_delay_s != 0) {
      double steps = e.actuator_delay_s / h_;
      if (std::fabs(steps - std::round(steps)) < 1e-9) steps = std::round(steps);
      delay_steps_ = static_cast<int>(std::floor(steps));
      delay_frac_ = steps - delay_steps_;
    }
  }
  if (e.spring_softening != 0) {
    for (int k = 0; k < body_->link_count(); ++k) {
      dJointID axial = body_->axial_joint(k);
      axial_joints_.push_back(axial);
      axial_erp_.push_back(dJointGetDBallParam(axial, dParamERP));
    }
  }
}

void CaterpillarSim::MeasureLengths() {
  lengths_.resize(body_->actuators().size());
  for (size_t i = 0; i < lengths_.size(); ++i) {
    Vec3 r, f;
    double rate;
    body_->ActuatorState(body_->actuators()[i], r, f, lengths_[i], rate);
  }
}

// Per actuator: ON, the constant push (paper, 8.8 N); always, the return spring, zero at
// min length; then the stroke stops. Stroke limits are off every joint axis, so each is a
// one-row contact joint along the actuator line (ode-notes.md, "Contact"), created while
// the length predicted for the end of the step, with a margin of the largest length change
// one step of actuator force can add, reaches a limit. Speculative: dContactMotionN lets the
// length close the remaining gap in this step but not pass it; a length already past the
// limit is pushed back by stop_erp.
//
// Effects: with actuator_delay_s the command is the mask of d seconds ago (DelayedCommand);
// with actuator_lag_s the ON push follows force_n times the command through a first-order
// lag, exact for a command held over the step: p <- c + (p - c) exp(-h / tau).
void CaterpillarSim::ApplyActuators(uint32_t on_mask) {
  const auto& a = params_.actuators;
  const double margin =
      h_ * h_ * 2 * a.force_n / (params_.lumps.mass_kg / body_->parts_per_lump());
  if (shaped_push_) {
    mask_history_.push_back(on_mask);
    while (static_cast<int>(mask_history_.size()) > delay_steps_ + 2) mask_history_.pop_front();
  }
  for (size_t i = 0; i < body_->actuators().size(); ++i) {
    const auto& act = body_->actuators()[i];
    Vec3 r, f;
    double len, rate;
    body_->ActuatorState(act, r, f, len, rate);
    const bool on = (on_mask >> act.index) & 1u;
    double on_push = on ? a.force_n : 0.0;
    if (shaped_push_) {
      const double command = DelayedCommand(act.index) * a.force_n;
      push_[i] = params_.effects.actuator_lag_s != 0
                     ? command + (push_[i] - command) * lag_keep_
                     : command;
      on_push = push_[i];
    }
    const double push = on_push - a.return_spring_n_per_m * (len - a.min_length_m);
    const double ux = (f.x - r.x) / len, uy = (f.y - r.y) / len, uz = (f.z - r.z) / len;
    dBodyAddForceAtPos(act.front, push * ux, push * uy, push * uz, f.x, f.y, f.z);
    dBodyAddForceAtPos(act.rear, -push * ux, -push * uy, -push * uz, r.x, r.y, r.z);
    if (params_.effects.actuator_deadband_n > 0) AddActuatorDeadband(act, r, f, ux, uy, uz);

    const double predicted = len + h_ * rate;
    const bool at_max = predicted + margin >= a.max_length_m;
    const bool at_min = predicted - margin <= a.min_length_m;
    if (!at_max && !at_min) continue;
    dContact c = FrictionlessContact();
    c.surface.mode |= dContactSoftERP | dContactSoftCFM | dContactMotionN;
    c.surface.soft_erp = a.stop_erp;
    c.surface.soft_cfm = a.stop_cfm;
    const double gap = at_max ? a.max_length_m - len : len - a.min_length_m;
    c.geom.pos[0] = 0.5 * (r.x + f.x);  // on the actuator line: forces act along it
    c.geom.pos[1] = 0.5 * (r.y + f.y);
    c.geom.pos[2] = 0.5 * (r.z + f.z);
    c.geom.normal[0] = ux;
    c.geom.normal[1] = uy;
    c.geom.normal[2] = uz;
    c.geom.depth = gap < 0 ? -gap : 0;
    c.surface.motionN = gap > 0 ? -gap / h_ : 0;
    dJointID j = dJointCreateContact(world_.world(), world_.contacts(), &c);
    // Body 1 is pushed along +normal: the rear lump at the max stop, the front at the min.
    if (at_max) {
      dJointAttach(j, act.rear, act.front);
    } else {
      dJointAttach(j, act.front, act.rear);
    }
  }
}

// The deadband (effects.actuator_deadband_n): Coulomb friction of the piston, a row along
// the actuator line with zero target rate, bounded by +-F. ODE's symmetric bounded row is a
// contact's friction row (fdir1 along the line; mu without dContactApprox1 is a force
// limit in newtons): on the line, the relative velocity at its midpoint along the line is
// exactly the rate of the length. The contact's normal (across the line, in the x-z plane)
// is made inert by a very soft CFM (at most about 1e-3 N for speeds of 1 m/s), and slip1
// gives the friction row the stop rows' softness, so that both may act at a stop.
void CaterpillarSim::AddActuatorDeadband(const ActuatorGeometry& act, const Vec3& r,
                                         const Vec3& f, double ux, double uy, double uz) {
  dContact c{};
  c.surface.mode = dContactMu2 | dContactFDir1 | dContactSoftCFM | dContactSlip1;
  c.surface.mu = params_.effects.actuator_deadband_n;
  c.surface.mu2 = 0;
  c.surface.soft_cfm = 1e3;
  c.surface.slip1 = params_.actuators.stop_cfm;
  c.geom.pos[0] = 0.5 * (r.x + f.x);
  c.geom.pos[1] = 0.5 * (r.y + f.y);
  c.geom.pos[2] = 0.5 * (r.z + f.z);
  const double n = std::hypot(ux, uz);
  if (n < 1e-9) return;  // a line along y cannot happen in the planar robot
  c.geom.normal[0] = -uz / n;  // u turned a quarter about y: across the line, in the plane
  c.geom.normal[1] = 0;
  c.geom.normal[2] = ux / n;
  c.geom.depth = 0;
  c.fdir1[0] = ux;
  c.fdir1[1] = uy;
  c.fdir1[2] = uz;
  dJointAttach(dJointCreateContact(world_.world(), world_.contacts(), &c), act.front, act.rear);
}

double CaterpillarSim::DelayedCommand(int index) const {
  // Over this step the delayed command is mask[n - D - 1] for the first `frac` of the step
  // and mask[n - D] for the rest; masks before the start are 0 (OFF).
  const int n = static_cast<int>(mask_history_.size()) - 1;  // this step's mask
  auto bit = [&](int back) -> double {
    const int i = n - back;
    return i >= 0 && ((mask_history_[i] >> index) & 1u) ? 1.0 : 0.0;
  };
  const double newer = bit(delay_steps_);
  return delay_frac_ != 0 ? delay_frac_ * bit(delay_steps_ + 1) + (1 - delay_frac_) * newer
                          : newer;
}

// Tether, drag and softening springs (params.effects), each skipped at zero. Forces act at
// the lump centres with the state at the start of the step (explicit).
void CaterpillarSim::ApplyEffects() {
  const auto& e = params_.effects;
  if ((e.tether_force_n != 0 || e.tether_stiffness_n_per_m != 0) &&
      body_->options().first_lump == 1) {
    double pull = e.tether_force_n;
    if (e.tether_stiffness_n_per_m != 0) {
      pull += e.tether_stiffness_n_per_m * std::max(0.0, body_->Position(0).x - start_[0].x);
    }
    body_->AddLumpForce(0, -pull, 0, 0);
  }
  if (e.drag_n_s_per_m != 0) {
    // Per body: a split lump's halves share its coefficient.
    const double c = e.drag_n_s_per_m / body_->parts_per_lump();
    for (int i = 0; i < body_->body_count(); ++i) {
      const dReal* v = dBodyGetLinearVel(body_->body(i));
      dBodyAddForce(body_->body(i), -c * v[0], 0, -c * v[2]);
    }
  }
  if (e.spring_softening != 0) {
    // ERP = h k / c: scaling it scales the spring and leaves the damper c (CFM) alone.
    for (size_t k = 0; k < axial_joints_.size(); ++k) {
      const double sx = e.spring_softening * body_->LinkExtension(static_cast<int>(k));
      dJointSetDBallParam(axial_joints_[k], dParamERP, axial_erp_[k] / std::sqrt(1 + sx * sx));
    }
  }
}

// The ground z = 0 touches the corners of each body's x-z section (a lump, or a half-lump
// when split): the bottom face's front and rear edges when flat, any corner after a flip.
// Motion is planar, so one contact per edge on the centre plane stands for the box's two
// corners. Infinite friction (paper) is an unbounded row along x; a body needs one (on its
// deepest corner), since the friction rows
// of two corners on one face would be the same row twice. None is needed across the plane.
// Anisotropic friction (effects.friction_forward/backward): the coefficient of the lump's
// direction of motion at the start of the step, finite (dContactApprox1: each row bounded
// by mu times its own contact's normal force); a direction at 0 keeps the ground's own
// friction. These finite rows go on every touching corner, so the bound is mu times the
// lump's whole normal force (Coulomb: a passive lump on a slope slides at
// g (sin s - mu cos s)). Bounded rows may repeat each other; the infinite row may not.
// (ground.friction_coefficient keeps its single row on the deepest corner, bounded by that
// corner's share of the normal force: about mu/2 of the weight for a flat lump.)
void CaterpillarSim::AddGroundContacts() {
  ground_contacts_ = 0;
  if (!body_->options().ground) return;
  const auto& L = params_.lumps;
  const auto& g = params_.ground;
  const auto& e = params_.effects;
  const bool anisotropic = e.friction_forward != 0 || e.friction_backward != 0;
  const int base_mode = dContactMu2 | dContactFDir1 | dContactSoftERP | dContactSoftCFM;
  dContact c{};
  c.surface.mode = base_mode;
  if (!g.infinite_friction) c.surface.mode |= dContactApprox1;
  c.surface.mu2 = 0;
  c.surface.soft_erp = g.contact_erp;
  c.surface.soft_cfm = g.contact_cfm;
  c.geom.normal[2] = 1;
  c.fdir1[0] = 1;
  const double size_x = body_->body_size_x();
  for (int k = 0; k < body_->body_count(); ++k) {
    dBodyID b = body_->body(k);
    double lump_mu = g.infinite_friction ? dInfinity : g.friction_coefficient;
    bool every_corner = false;
    if (anisotropic) {
      const double mu = dBodyGetLinearVel(b)[0] >= 0 ? e.friction_forward : e.friction_backward;
      const bool finite = mu > 0 || !g.infinite_friction;
      if (mu > 0) lump_mu = mu;
      every_corner = mu > 0;
      c.surface.mode = base_mode | (finite ? dContactApprox1 : 0);
    }
    dVector3 corners[4];
    int deepest = -1;
    for (int corner = 0; corner < 4; ++corner) {
      const double cx = (corner & 1 ? 0.5 : -0.5) * size_x;
      const double cz = (corner & 2 ? 0.5 : -0.5) * L.size_z_m;
      dBodyGetRelPointPos(b, cx, 0, cz, corners[corner]);
      if (corners[corner][2] <= 0 && (deepest < 0 || corners[corner][2] < corners[deepest][2])) {
        deepest = corner;
      }
    }
    for (int corner = 0; corner < 4; ++corner) {
      const dReal* p = corners[corner];
      if (p[2] > 0) continue;
      c.geom.pos[0] = p[0];
      c.geom.pos[1] = p[1];
      c.geom.pos[2] = p[2];
      c.geom.depth = -p[2];
      c.surface.mu = corner == deepest || every_corner ? lump_mu : 0;
      dJointAttach(dJointCreateContact(world_.world(), world_.contacts(), &c), b, nullptr);
      ++ground_contacts_;
    }
  }
}

// Bodies (lumps or half-lumps) that are not neighbours may touch when the body folds;
// neighbours always overlap at the link and must not collide (unfiltered, they made the
// no-slip feet slide). Pairs whose centres are farther apart than a box diagonal cannot
// touch and are skipped.
void CaterpillarSim::AddLumpContacts() {
  const auto& L = params_.lumps;
  const double x = body_->body_size_x();
  const double reach2 = x * x + L.size_y_m * L.size_y_m + L.size_z_m * L.size_z_m;
  const int n = body_->body_count();
  for (int i = 0; i < n; ++i) {
    for (int j = i + 2; j < n; ++j) {
      const dReal* a = dBodyGetPosition(body_->body(i));
      const dReal* b = dBodyGetPosition(body_->body(j));
      const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
      if (dx * dx + dy * dy + dz * dz > reach2) continue;
      dContactGeom geoms[8];
      const int count = dCollide(body_->geom(i), body_->geom(j), 8, geoms, sizeof(dContactGeom));
      for (int k = 0; k < count; ++k) {
        dContact c = FrictionlessContact();
        c.geom = geoms[k];
        // Fold onto the centre plane: forces stay in x-z.
        c.geom.pos[1] = 0;
        c.geom.normal[1] = 0;
        const double len = std::hypot(c.geom.normal[0], c.geom.normal[2]);
        if (len < 1e-6) continue;
        c.geom.normal[0] /= len;
        c.geom.normal[2] /= len;
        dJointAttach(dJointCreateContact(world_.world(), world_.contacts(), &c), body_->body(i),
                     body_->body(j));
      }
    }
  }
}

sim::SimOutcome CaterpillarSim::Step(uint32_t on_mask) {
  const std::vector<double> before = lengths_;
  try {
    ApplyActuators(on_mask);
    ApplyEffects();
    AddGroundContacts();
    AddLumpContacts();
    body_->UpdateLinkAngles();
    world_.Step(h_);
  } catch (const sim::OdeError& e) {
    ++steps_;
    std::ostringstream out;
    out << e.what() << " at t = " << time() << " s";
    return sim::SimOutcome::Failed(out.str());
  }
  ++steps_;
  MeasureLengths();
  last_work_ = 0;
  for (size_t i = 0; i < lengths_.size(); ++i) {
    if (shaped_push_) {
      last_work_ += push_[i] * (lengths_[i] - before[i]);
    } else if ((on_mask >> body_->actuators()[i].index) & 1u) {
      last_work_ += params_.actuators.force_n * (lengths_[i] - before[i]);
    }
  }
  return CheckState();
}

sim::SimOutcome CaterpillarSim::CheckState() {
  const auto& s = params_.simulation;
  const auto& a = params_.actuators;
  auto fail = [&](const std::string& what) {
    std::ostringstream out;
    out << "diverged at t = " << time() << " s: " << what
        << " (h*omega_max = " << body_->MaxStepOmega(h_)
        << "; stable while (h omega)^2 < 4 + 4 zeta h omega)";
    return sim::SimOutcome::Failed(out.str());
  };
  const double max_spin = 2 * s.max_speed_m_per_s / params_.lumps.size_x_m;
  for (int k = 0; k < body_->body_count(); ++k) {
    const int lump = body_->options().first_lump + k / body_->parts_per_lump();
    const dReal* p = dBodyGetPosition(body_->body(k));
    const dReal* v = dBodyGetLinearVel(body_->body(k));
    const dReal* w = dBodyGetAngularVel(body_->body(k));
    for (int i = 0; i < 3; ++i) {
      if (!std::isfinite(p[i]) || !std::isfinite(v[i]) || !std::isfinite(w[i])) {
        return fail("non-finite state of lump " + std::to_string(lump));
      }
    }
    const double speed = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    const double spin = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
    const Vec3& s0 = body_start_[k];
    const double dx = p[0] - s0.x, dy = p[1] - s0.y, dz = p[2] - s0.z;
    if (speed > s.max_speed_m_per_s) {
      return fail("lump " + std::to_string(lump) + " speed " + std::to_string(speed) + " m/s");
    }
    if (spin > max_spin) {
      return fail("lump " + std::to_string(lump) + " spin " + std::to_string(spin) + " rad/s");
    }
    if (std::sqrt(dx * dx + dy * dy + dz * dz) > s.max_excursion_m) {
      return fail("lump " + std::to_string(lump) + " left the " +
                  std::to_string(s.max_excursion_m) + " m region");
    }
  }
  for (size_t i = 0; i < lengths_.size(); ++i) {
    if (lengths_[i] < a.min_length_m - a.overrun_tolerance_m ||
        lengths_[i] > a.max_length_m + a.overrun_tolerance_m) {
      static const char* kNames[] = {"T1", "T2", "T3", "B1", "B2", "B3"};
      std::ostringstream out;
      out << "actuator " << kNames[body_->actuators()[i].index] << " length " << lengths_[i]
          << " m beyond its stroke [" << a.min_length_m << ", " << a.max_length_m
          << "] m by more than " << a.overrun_tolerance_m << " m";
      return fail(out.str());
    }
  }
  return sim::SimOutcome::Ok();
}

}  // namespace gaitforge::caterpillar
