// GenericWorld's parts for planar robots (generic_world.h): spring links, pistons, ground
// contacts on the centre plane and self-contacts, for lumped soft robots that move in a
// plane.
#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "workers/models/generic/generic_world.h"
#include "workers/models/generic/param_eval.h"

namespace gaitforge::generic {
namespace {

// A spring-damper as a soft constraint row (../shared/guides/ode-notes.md, "Springs and
// dampers"). ODE solves J v' = -(ERP/h) x - CFM f for the row force f, i.e.
// f = -k x - (hk + c') v' with ERP = hk/(hk + c'), CFM = 1/(hk + c'). With c' = c - hk this
// is f = -k x_n - c v_{n+1}: the damper implicit and the spring symplectic Euler, stable
// while (h omega)^2 < 4 + 4 zeta h omega.
struct SoftRow {
  double erp, cfm;
};
SoftRow SpringDamper(double k, double c, double h) { return {h * k / c, 1.0 / c}; }

// The shear row's point sits this far from the anchor, across the link: far, so that its
// second-order pull from an axial slide s, s^2 / (2 kShearLeverM), stays below 0.1 mm.
constexpr double kShearLeverM = 1.0;

// Rotation of a body about +y (rad); +pitch turns +x towards -z (nose down).
double BodyPitch(dBodyID b) {
  const dReal* r = dBodyGetRotation(b);  // 3x4 row-major; column 0 is body x
  return std::atan2(-r[8], r[0]);
}

// A contact with no friction row: self-contacts and stroke stops.
dContact FrictionlessContact() {
  dContact c{};
  c.surface.mode = dContactMu2;
  c.surface.mu = 0;
  c.surface.mu2 = 0;
  return c;
}

}  // namespace

absl::Status GenericWorld::BuildSpringLink(const robots::Joint& j, const ParamValues& v) {
  const auto anchor = Eval(j.anchor, v);
  const double length = Eval(*j.length, v), k = Eval(*j.axial_stiffness, v);
  const double kappa = Eval(*j.stiffness, v);
  const double zeta = Eval(*j.axial_damping_ratio, v), zeta_bend = Eval(*j.damping_ratio, v);
  if (!(length > 0 && k > 0 && kappa > 0 && zeta > 0 && zeta_bend > 0))
    return absl::InvalidArgumentError(absl::StrCat(
        j.mark.ToString(), ": spring_link ", j.name,
        " needs length, axial_stiffness, stiffness and both damping ratios > 0"));
  const int i1 = BodyIndex(j.body1), i2 = BodyIndex(j.body2);
  const int b1 = NearPart(i1, anchor), b2 = NearPart(i2, anchor);
  // On a split body the axial spring's point moves to the centre of the half that holds
  // the anchor's side: a quarter of the body's length along the link.
  const Built& from = built_[i1];
  const double shift = from.parts == 1 ? 0.0 : b1 == from.first ? -from.half_x : from.half_x;
  std::array<double, 3> p1;
  for (int c = 0; c < 3; ++c) p1[c] = anchor[c] - length * j.axis[c] + shift * j.axis[c];
  // Damped as fractions of critical for the two bodies as the descriptor gives them (whole,
  // even when split).
  const Built& to = built_[i2];
  AddLink(bodies_[b1], bodies_[b2], anchor, j.axis, p1, k, kappa,
          Damping(zeta, k, from.mass, to.mass), Damping(zeta_bend, kappa, from.inertia_y, to.inertia_y));
  return absl::OkStatus();
}

void GenericWorld::AddLink(dBodyID b1, dBodyID b2, const std::array<double, 3>& anchor,
                           const std::array<double, 3>& a, const std::array<double, 3>& p1,
                           double k, double kappa, double c_axial, double c_bend) {
  Link link{nullptr, nullptr, nullptr, b1, b2};
  const dReal erp = dWorldGetERP(world_.world()), cfm = dWorldGetCFM(world_.world());
  link.shear = dJointCreateDBall(world_.world(), nullptr);
  dJointAttach(link.shear, b1, b2);
  // Across the link, in the plane: axis x y.
  dJointSetDBallAnchor1(link.shear, anchor[0] - kShearLeverM * a[2], anchor[1],
                        anchor[2] + kShearLeverM * a[0]);
  dJointSetDBallAnchor2(link.shear, anchor[0], anchor[1], anchor[2]);
  dJointSetDBallParam(link.shear, dParamERP, erp);
  dJointSetDBallParam(link.shear, dParamCFM, cfm);

  link.axial = dJointCreateDBall(world_.world(), nullptr);
  dJointAttach(link.axial, b1, b2);
  dJointSetDBallAnchor1(link.axial, p1[0], p1[1], p1[2]);
  dJointSetDBallAnchor2(link.axial, anchor[0], anchor[1], anchor[2]);
  const SoftRow axial = SpringDamper(k, c_axial, h_);
  dJointSetDBallParam(link.axial, dParamERP, axial.erp);
  link.axial_erp = axial.erp;
  dJointSetDBallParam(link.axial, dParamCFM, axial.cfm);

  link.bend = dJointCreateAMotor(world_.world(), nullptr);
  dJointAttach(link.bend, b1, b2);
  dJointSetAMotorMode(link.bend, dAMotorUser);
  dJointSetAMotorNumAxes(link.bend, 1);
  dJointSetAMotorAxis(link.bend, 0, 1, 0, 1, 0);  // y, fixed in body 1
  const SoftRow bend = SpringDamper(kappa, c_bend, h_);
  dJointSetAMotorParam(link.bend, dParamHiStop, 0);
  dJointSetAMotorParam(link.bend, dParamLoStop, 0);  // lo = hi: a two-sided row
  dJointSetAMotorParam(link.bend, dParamStopERP, bend.erp);
  dJointSetAMotorParam(link.bend, dParamStopCFM, bend.cfm);
  dJointSetAMotorAngle(link.bend, 0, 0);
  links_.push_back(link);
}

double GenericWorld::Damping(double zeta, double k, double a, double b) {
  return 2 * zeta * std::sqrt(a == b ? k * a / 2 : k * (a * b / (a + b)));
}

double GenericWorld::Bend(const Link& l) {
  return std::remainder(BodyPitch(l.b2) - BodyPitch(l.b1), 2 * M_PI);
}

double GenericWorld::LinkBend(int joint) const {
  const int k = joint_link_.at(joint);
  return k < 0 ? 0.0 : Bend(links_[k]);
}

// The axial row holds a distance between its two anchors: the extension is the distance
// now less the one at rest.
double GenericWorld::LinkExtension(int joint) const {
  const int k = joint_link_.at(joint);
  if (k < 0) return 0.0;
  dVector3 a1, a2;
  dJointGetDBallAnchor1(links_[k].axial, a1);
  dJointGetDBallAnchor2(links_[k].axial, a2);
  const double dx = a2[0] - a1[0], dy = a2[1] - a1[1], dz = a2[2] - a1[2];
  return std::sqrt(dx * dx + dy * dy + dz * dz) - dJointGetDBallDistance(links_[k].axial);
}

// ODE's limit row is J = [axis, -axis] on (body 1, body 2) angular velocity, so the angle it
// expects grows with body 1's rotation relative to body 2: minus the bend.
void GenericWorld::UpdateLinkAngles() {
  for (const Link& l : links_) dJointSetAMotorAngle(l.bend, 0, -Bend(l));
}

absl::Status GenericWorld::BuildPiston(const robots::Actuator& a, int index,
                                       const ParamValues& v) {
  Piston p;
  p.actuator = index;
  const auto [b1, p1] = Locate(BodyIndex(a.body1), Eval(a.attach1, v));
  const auto [b2, p2] = Locate(BodyIndex(a.body2), Eval(a.attach2, v));
  p.b1 = bodies_[b1];
  p.b2 = bodies_[b2];
  p.p1 = p1;
  p.p2 = p2;
  p.force = Eval(a.force, v);
  p.k = Eval(a.return_stiffness, v);
  p.min = Eval(a.min_length, v);
  p.max = Eval(a.max_length, v);
  p.stop_erp = Eval(a.stop_erp, v);
  p.stop_cfm = Eval(a.stop_cfm, v);
  p.tolerance = Eval(a.overrun_tolerance, v);
  dMass m1, m2;
  dBodyGetMass(p.b1, &m1);
  dBodyGetMass(p.b2, &m2);
  p.lighter_mass = std::min(m1.mass, m2.mass);
  if (!(p.force >= 0 && p.k >= 0 && p.min > 0 && p.max > p.min && p.stop_erp > 0 &&
        p.stop_erp <= 1 && p.stop_cfm >= 0 && p.tolerance > 0))
    return absl::InvalidArgumentError(absl::StrCat(
        a.mark.ToString(), ": piston ", a.name,
        " needs force >= 0, return_stiffness >= 0, 0 < min_length < max_length, stop_erp in "
        "(0, 1], stop_cfm >= 0 and overrun_tolerance > 0"));
  pistons_.push_back(p);
  const PistonState s = StateOf(p);
  if (s.length < p.min - p.tolerance || s.length > p.max + p.tolerance)
    return absl::InvalidArgumentError(absl::StrCat(
        a.mark.ToString(), ": piston ", a.name, " starts ", s.length, " m long, outside its stroke [",
        p.min, ", ", p.max, "] m"));
  piston_lengths_.push_back(s.length);
  piston_extensions_.push_back(s.length - p.min);
  return absl::OkStatus();
}

GenericWorld::PistonState GenericWorld::StateOf(const Piston& p) {
  dVector3 pr, pf, vr, vf;
  dBodyGetRelPointPos(p.b1, p.p1[0], p.p1[1], p.p1[2], pr);
  dBodyGetRelPointPos(p.b2, p.p2[0], p.p2[1], p.p2[2], pf);
  dBodyGetRelPointVel(p.b1, p.p1[0], p.p1[1], p.p1[2], vr);
  dBodyGetRelPointVel(p.b2, p.p2[0], p.p2[1], p.p2[2], vf);
  PistonState s;
  const double dx = pf[0] - pr[0], dy = pf[1] - pr[1], dz = pf[2] - pr[2];
  s.length = std::sqrt(dx * dx + dy * dy + dz * dz);
  s.rate = ((vf[0] - vr[0]) * dx + (vf[1] - vr[1]) * dy + (vf[2] - vr[2]) * dz) / s.length;
  s.r = {pr[0], pr[1], pr[2]};
  s.f = {pf[0], pf[1], pf[2]};
  return s;
}

// Per piston: the push (command times force) less the return spring, zero at min length;
// then the stroke stops. They are off every joint axis, so each is a one-row contact along
// the piston's line (ode-notes.md, "Contact"), created while the length predicted for the
// end of the step, with a margin of the largest change one step of force can add, reaches
// a limit. Speculative: dContactMotionN lets the length close the remaining gap in this
// step but not pass it; a length already past the limit is pushed back by stop_erp.
//
// Effects: with effect.actuator_lag_s the push follows command times force through a
// first-order lag, exact for a command held over the step: p <- c + (p - c) exp(-h / tau),
// from 0 at rest; with effect.actuator_deadband_n a friction row along the line.
void GenericWorld::ApplyPistons(const std::vector<double>& commands) {
  const double lag_keep = fx_.actuator_lag > 0 ? std::exp(-h_ / fx_.actuator_lag) : 0;
  for (Piston& p : pistons_) {
    const PistonState s = StateOf(p);
    const double command = static_cast<size_t>(p.actuator) < commands.size() ? commands[p.actuator] : 0.0;
    const double target = command * p.force;
    p.push = fx_.actuator_lag > 0 ? target + (p.push - target) * lag_keep : target;
    const double push = p.push - p.k * (s.length - p.min);
    const auto& r = s.r;
    const auto& f = s.f;
    const double ux = (f[0] - r[0]) / s.length, uy = (f[1] - r[1]) / s.length,
                 uz = (f[2] - r[2]) / s.length;
    dBodyAddForceAtPos(p.b2, push * ux, push * uy, push * uz, f[0], f[1], f[2]);
    dBodyAddForceAtPos(p.b1, -push * ux, -push * uy, -push * uz, r[0], r[1], r[2]);
    if (fx_.piston_deadband > 0) AddPistonDeadband(p, s, ux, uy, uz);

    const double margin = h_ * h_ * 2 * p.force / p.lighter_mass;
    const double predicted = s.length + h_ * s.rate;
    const bool at_max = predicted + margin >= p.max;
    const bool at_min = predicted - margin <= p.min;
    if (!at_max && !at_min) continue;
    dContact c = FrictionlessContact();
    c.surface.mode |= dContactSoftERP | dContactSoftCFM | dContactMotionN;
    c.surface.soft_erp = p.stop_erp;
    c.surface.soft_cfm = p.stop_cfm;
    const double gap = at_max ? p.max - s.length : s.length - p.min;
    for (int k = 0; k < 3; ++k) c.geom.pos[k] = 0.5 * (r[k] + f[k]);  // on the line
    c.geom.normal[0] = ux;
    c.geom.normal[1] = uy;
    c.geom.normal[2] = uz;
    c.geom.depth = gap < 0 ? -gap : 0;
    c.surface.motionN = gap > 0 ? -gap / h_ : 0;
    dJointID j = dJointCreateContact(world_.world(), world_.contacts(), &c);
    // Body 1 is pushed along +normal: the rear body at the max stop, the front at the min.
    if (at_max) {
      dJointAttach(j, p.b1, p.b2);
    } else {
      dJointAttach(j, p.b2, p.b1);
    }
  }
}

// The deadband (effect.actuator_deadband_n): Coulomb friction of the piston, a row along
// its line with zero target rate, bounded by +-F. ODE's symmetric bounded row is a
// contact's friction row (fdir1 along the line; mu without dContactApprox1 is a force
// limit in newtons): at the line's midpoint, the relative velocity along the line is the
// rate of the length. The contact's normal (across the line, in the x-z plane) is made
// inert by a very soft CFM (about 1e-3 N at 1 m/s), and slip1 gives the friction row the
// stops' softness, so that both may act at a stop.
void GenericWorld::AddPistonDeadband(const Piston& p, const PistonState& s, double ux,
                                     double uy, double uz) {
  dContact c{};
  c.surface.mode = dContactMu2 | dContactFDir1 | dContactSoftCFM | dContactSlip1;
  c.surface.mu = fx_.piston_deadband;
  c.surface.mu2 = 0;
  c.surface.soft_cfm = 1e3;
  c.surface.slip1 = p.stop_cfm;
  for (int k = 0; k < 3; ++k) c.geom.pos[k] = 0.5 * (s.r[k] + s.f[k]);
  const double n = std::hypot(ux, uz);
  if (n < 1e-9) return;  // a line along y: not in a planar robot
  c.geom.normal[0] = -uz / n;  // u turned a quarter about y: across the line, in the plane
  c.geom.normal[1] = 0;
  c.geom.normal[2] = ux / n;
  c.geom.depth = 0;
  c.fdir1[0] = ux;
  c.fdir1[1] = uy;
  c.fdir1[2] = uz;
  dJointAttach(dJointCreateContact(world_.world(), world_.contacts(), &c), p.b2, p.b1);
}

// effect.spring_softening: ERP = h k / c, so scaling it scales the spring and leaves the
// damper (CFM) alone; axial force k x / sqrt(1 + (sigma x)^2) with the extension at the
// start of the step.
void GenericWorld::SoftenLinks() {
  for (const Link& l : links_) {
    dVector3 a1, a2;
    dJointGetDBallAnchor1(l.axial, a1);
    dJointGetDBallAnchor2(l.axial, a2);
    const double x = std::sqrt((a2[0] - a1[0]) * (a2[0] - a1[0]) + (a2[1] - a1[1]) * (a2[1] - a1[1]) +
                               (a2[2] - a1[2]) * (a2[2] - a1[2])) -
                     dJointGetDBallDistance(l.axial);
    const double sx = fx_.spring_softening * x;
    dJointSetDBallParam(l.axial, dParamERP, l.axial_erp / std::sqrt(1 + sx * sx));
  }
}

void GenericWorld::MeasurePistons() {
  piston_work_ = 0;
  for (size_t i = 0; i < pistons_.size(); ++i) {
    const double length = StateOf(pistons_[i]).length;
    piston_work_ += pistons_[i].push * (length - piston_lengths_[i]);
    piston_lengths_[i] = length;
    piston_extensions_[i] = length - pistons_[i].min;
  }
}

sim::SimOutcome GenericWorld::CheckPistons() const {
  for (size_t i = 0; i < pistons_.size(); ++i) {
    const Piston& p = pistons_[i];
    const double len = piston_lengths_[i];
    if (len >= p.min - p.tolerance && len <= p.max + p.tolerance) continue;
    return sim::SimOutcome::Failed(absl::StrCat(
        "diverged at t = ", time(), " s: piston ", d_.actuators[p.actuator].name, " length ", len,
        " m beyond its stroke [", p.min, ", ", p.max, "] m by more than ", p.tolerance, " m"));
  }
  return sim::SimOutcome::Ok();
}

// The ground z = 0 touches the corners of each box's x-z section: the bottom face's front
// and rear edges when flat, any corner after a flip. Motion is planar, so one contact per
// edge on the centre plane stands for the box's two corners. Friction acts along x only,
// on the deepest corner (the friction rows of two corners of one face would be one row
// twice); an infinite coefficient is an unbounded row. A direction-dependent coefficient
// (effect friction_forward/backward, by the sign of the body's x velocity at the start of
// the step; 0 keeps the ground's own) is finite and goes on every touching corner, each
// row bounded by mu times its own corner's normal force (dContactApprox1), so the bound is
// mu times the body's whole normal force. A creeping contact (effect.contact_slip_m_per_n_s)
// gives each friction row ODE's force-dependent slip: it slides at slip times its force.
void GenericWorld::AddPlanarGroundContacts() {
  ground_contacts_ = 0;
  const bool anisotropic = fx_.friction_forward != 0 || fx_.friction_backward != 0;
  const int base_mode = dContactMu2 | dContactFDir1 | dContactSoftERP | dContactSoftCFM |
                        (fx_.contact_slip > 0 ? dContactSlip1 : 0);
  for (size_t i = 0; i < bodies_.size(); ++i) {
    const dBodyID b = bodies_[i];
    const bool infinite = std::isinf(body_friction_[i]);
    dContact c{};
    c.surface.mode = base_mode | (infinite ? 0 : dContactApprox1);
    c.surface.mu2 = 0;
    c.surface.soft_erp = contact_erp_;
    c.surface.soft_cfm = contact_cfm_;
    c.surface.slip1 = fx_.contact_slip;
    c.geom.normal[2] = 1;
    c.fdir1[0] = 1;
    double mu = infinite ? dInfinity : body_friction_[i];
    bool every_corner = false;
    if (anisotropic) {
      const double directed = dBodyGetLinearVel(b)[0] >= 0 ? fx_.friction_forward : fx_.friction_backward;
      if (directed > 0) mu = directed;
      every_corner = directed > 0;
      c.surface.mode = base_mode | (directed > 0 || !infinite ? dContactApprox1 : 0);
    }
    dVector3 corners[4];
    int deepest = -1;
    for (int corner = 0; corner < 4; ++corner) {
      const double cx = (corner & 1 ? 0.5 : -0.5) * sizes_[i][0];
      const double cz = (corner & 2 ? 0.5 : -0.5) * sizes_[i][2];
      dBodyGetRelPointPos(b, cx, 0, cz, corners[corner]);
      if (corners[corner][2] <= -contact_depth_[i] &&
          (deepest < 0 || corners[corner][2] < corners[deepest][2]))
        deepest = corner;
    }
    for (int corner = 0; corner < 4; ++corner) {
      const dReal* p = corners[corner];
      if (p[2] > -contact_depth_[i]) continue;
      for (int k = 0; k < 3; ++k) c.geom.pos[k] = p[k];
      c.geom.depth = -p[2] - contact_depth_[i];
      c.surface.mu = corner == deepest || every_corner ? mu : 0;
      dJointAttach(dJointCreateContact(world_.world(), world_.contacts(), &c), b, nullptr);
      ++ground_contacts_;
    }
  }
}

// Bodies that no joint joins touch when the robot folds (frictionless); joined bodies
// overlap at their joint and must not collide. Pairs whose centres are farther apart than
// their half-diagonals together cannot touch and are skipped. A planar robot's contacts are
// folded onto its plane, so that forces stay in x-z.
void GenericWorld::AddSelfContacts() {
  for (const ContactPair& pair : contact_pairs_) {
    const int i = pair.i, j = pair.j;
    const dReal* a = dBodyGetPosition(bodies_[i]);
    const dReal* b = dBodyGetPosition(bodies_[j]);
    const double dx = a[0] - b[0], dy = a[1] - b[1], dz = a[2] - b[2];
    if (dx * dx + dy * dy + dz * dz > pair.reach2) continue;
    dContactGeom geoms[8];
    const int count = dCollide(geoms_[i], geoms_[j], 8, geoms, sizeof(dContactGeom));
    for (int k = 0; k < count; ++k) {
      dContact c = FrictionlessContact();
      c.geom = geoms[k];
      if (!d_.plane.empty()) {
        c.geom.pos[1] = 0;
        c.geom.normal[1] = 0;
        const double len = std::hypot(c.geom.normal[0], c.geom.normal[2]);
        if (len < 1e-6) continue;
        c.geom.normal[0] /= len;
        c.geom.normal[2] /= len;
      }
      dJointAttach(dJointCreateContact(world_.world(), world_.contacts(), &c), bodies_[i],
                   bodies_[j]);
    }
  }
}

}  // namespace gaitforge::generic
