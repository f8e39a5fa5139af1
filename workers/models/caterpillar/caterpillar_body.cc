#include "workers/models/caterpillar/caterpillar_body.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace gaitforge::caterpillar {
namespace {

Vec3 FromOde(const dReal* v) { return {v[0], v[1], v[2]}; }

// Spring-damper as a soft constraint row (../shared/guides/ode-notes.md, "Springs and
// dampers"). ODE solves J v' = -(ERP/h) x - CFM f for the row force f, i.e.
// f = -k x - (hk + c') v' with ERP = hk/(hk + c'), CFM = 1/(hk + c'). With c' = c - hk this
// is f = -k x_n - c v_{n+1}: the damper implicit (no extra numerical damping; a 0.10 target
// measured 0.099) and the spring symplectic Euler: stable while
// (h omega)^2 < 4 + 4 zeta h omega (h omega < 4.8 at critical damping).
struct SoftRow {
  double erp, cfm;
};
SoftRow SpringDamper(double k, double c, double h) { return {h * k / c, 1.0 / c}; }

// Distance from a joint's reference point above the anchor: long, so that the shear row's
// second-order pull from an axial slide s, s^2 / (2 kShearLever), stays below 0.1 mm.
constexpr double kShearLeverM = 1.0;

// The silicone block between the centres of a split lump's halves (length l, the lump's y-z
// section): axial E A / l, bending E I / l.
LinkStiffness InnerStiffness(const CaterpillarParams::Lumps& L, double modulus_pa) {
  const double l = L.size_x_m / 2;
  const double area = L.size_y_m * L.size_z_m;
  const double second_moment = L.size_y_m * L.size_z_m * L.size_z_m * L.size_z_m / 12;
  return {modulus_pa * area / l, modulus_pa * second_moment / l};
}

// Largest h*omega of a split lump's inner link; past kMaxInnerStepOmega the lump is rigid.
constexpr double kMaxInnerStepOmega = 2.5;

// Rotation of a body about +y (rad); +pitch turns +x towards -z (nose down).
double BodyPitch(dBodyID b) {
  const dReal* r = dBodyGetRotation(b);  // 3x4 row-major; column 0 is body x
  return std::atan2(-r[8], r[0]);
}

double AxialExtension(dJointID axial) {
  dVector3 a1, a2;
  dJointGetDBallAnchor1(axial, a1);
  dJointGetDBallAnchor2(axial, a2);
  return std::sqrt((a2[0] - a1[0]) * (a2[0] - a1[0]) + (a2[1] - a1[1]) * (a2[1] - a1[1]) +
                   (a2[2] - a1[2]) * (a2[2] - a1[2])) -
         dJointGetDBallDistance(axial);
}

}  // namespace

CaterpillarBody::Link CaterpillarBody::MakeLink(dWorldID world, dBodyID rear, dBodyID front,
                                                double anchor_x, double rear_x,
                                                const LinkStiffness& s, double c_axial,
                                                double c_bend, double h) const {
  const double z0 = params_.lumps.size_z_m / 2;
  Link link{nullptr, nullptr, nullptr, rear, front, s.axial_n_per_m, s.bending_nm_per_rad};
  link.shear = dJointCreateDBall(world, nullptr);
  dJointAttach(link.shear, rear, front);
  dJointSetDBallAnchor1(link.shear, anchor_x, 0, z0 + kShearLeverM);
  dJointSetDBallAnchor2(link.shear, anchor_x, 0, z0);
  dJointSetDBallParam(link.shear, dParamERP, params_.simulation.solver_erp);
  dJointSetDBallParam(link.shear, dParamCFM, params_.simulation.solver_cfm);

  link.axial = dJointCreateDBall(world, nullptr);
  dJointAttach(link.axial, rear, front);
  dJointSetDBallAnchor1(link.axial, rear_x, 0, z0);
  dJointSetDBallAnchor2(link.axial, anchor_x, 0, z0);
  const SoftRow axial = SpringDamper(s.axial_n_per_m, c_axial, h);
  dJointSetDBallParam(link.axial, dParamERP, axial.erp);
  dJointSetDBallParam(link.axial, dParamCFM, axial.cfm);

  link.bend = dJointCreateAMotor(world, nullptr);
  dJointAttach(link.bend, rear, front);
  dJointSetAMotorMode(link.bend, dAMotorUser);
  dJointSetAMotorNumAxes(link.bend, 1);
  dJointSetAMotorAxis(link.bend, 0, 1, 0, 1, 0);  // y, fixed in the rear body
  const SoftRow bend = SpringDamper(s.bending_nm_per_rad, c_bend, h);
  dJointSetAMotorParam(link.bend, dParamHiStop, 0);
  dJointSetAMotorParam(link.bend, dParamLoStop, 0);  // lo = hi: a two-sided row
  dJointSetAMotorParam(link.bend, dParamStopERP, bend.erp);
  dJointSetAMotorParam(link.bend, dParamStopCFM, bend.cfm);
  dJointSetAMotorAngle(link.bend, 0, 0);
  return link;
}

CaterpillarBody::CaterpillarBody(dWorldID world, dSpaceID space, const CaterpillarParams& p,
                                 const BuildOptions& o, double h)
    : params_(p), options_(o) {
  if (o.first_lump < 1 || o.last_lump > 6 || o.first_lump > o.last_lump) {
    throw std::invalid_argument("BuildOptions: lumps must satisfy 1 <= first <= last <= 6");
  }
  const auto& L = p.lumps;
  const double z0 = L.size_z_m / 2;
  dMass lump_mass;
  dMassSetBoxTotal(&lump_mass, L.mass_kg, L.size_x_m, L.size_y_m, L.size_z_m);
  const double inertia_yy = lump_mass.I[1 * 4 + 1];

  // The model's resolution: split lumps when their material is soft enough to resolve.
  dMass half_mass;
  dMassSetBoxTotal(&half_mass, L.mass_kg / 2, L.size_x_m / 2, L.size_y_m, L.size_z_m);
  const double half_inertia_yy = half_mass.I[1 * 4 + 1];
  LinkStiffness inner{};
  double c_inner_axial = 0, c_inner_bend = 0;
  if (p.effects.lump_compliance_per_mpa > 0) {
    inner = InnerStiffness(L, 1e6 / p.effects.lump_compliance_per_mpa);
    const double omega = std::max(std::sqrt(inner.axial_n_per_m / (L.mass_kg / 4)),
                                  std::sqrt(inner.bending_nm_per_rad / (half_inertia_yy / 2)));
    if (h * omega <= kMaxInnerStepOmega) {
      parts_ = 2;
      c_inner_axial =
          2 * p.links.axial_damping_ratio * std::sqrt(inner.axial_n_per_m * L.mass_kg / 4);
      c_inner_bend = 2 * p.links.bending_damping_ratio *
                     std::sqrt(inner.bending_nm_per_rad * half_inertia_yy / 2);
      max_omega_ = omega;
    }
  }
  const double part_x = L.size_x_m / parts_;

  for (int i = o.first_lump; i <= o.last_lump; ++i) {
    const double centre = (i - 1) * L.spacing_m;
    for (int part = 0; part < parts_; ++part) {
      dBodyID b = dBodyCreate(world);
      dBodySetPosition(b, parts_ == 1 ? centre : centre + (part - 0.5) * part_x, 0, z0);
      dBodySetMass(b, parts_ == 1 ? &lump_mass : &half_mass);
      bodies_.push_back(b);
      dGeomID g = dCreateBox(space, part_x, L.size_y_m, L.size_z_m);
      dGeomSetBody(g, b);
      geoms_.push_back(g);
    }
    if (parts_ == 2) {
      const int n = static_cast<int>(bodies_.size());
      inner_links_.push_back(MakeLink(world, bodies_[n - 2], bodies_[n - 1], centre,
                                      centre - part_x / 2, inner, c_inner_axial, c_inner_bend,
                                      h));
    }
  }

  for (int k = 0; k + 1 < lump_count(); ++k) {
    const int i = o.first_lump + k;  // link (i, i+1)
    const LinkStiffness& s = p.Link(i);
    const double ax = (i - 0.5) * L.spacing_m;  // anchor, world frame at rest
    // Critical damping for the two-lump system (paper): reduced mass m/2, inertia I_yy/2.
    const double c_axial =
        2 * p.links.axial_damping_ratio * std::sqrt(s.axial_n_per_m * L.mass_kg / 2);
    const double c_bend =
        2 * p.links.bending_damping_ratio * std::sqrt(s.bending_nm_per_rad * inertia_yy / 2);
    // The rear body's centre: the lump's, or its front half's when split.
    const double rear_x = ax - L.spacing_m / 2 + (parts_ == 2 ? part_x / 2 : 0.0);
    links_.push_back(MakeLink(world, bodies_[parts_ * k + parts_ - 1], bodies_[parts_ * (k + 1)],
                              ax, rear_x, s, c_axial, c_bend, h));
    max_omega_ = std::max({max_omega_, std::sqrt(s.axial_n_per_m / (L.mass_kg / 2)),
                           std::sqrt(s.bending_nm_per_rad / (inertia_yy / 2))});
  }

  if (o.actuators) {
    const auto& a = p.actuators;
    // A point at x in a lump's frame: its body, and the point in that body's frame.
    auto attach = [&](int lump, double x) -> std::pair<dBodyID, double> {
      const int k = lump - o.first_lump;
      if (parts_ == 1) return {bodies_[k], x};
      return x < 0 ? std::pair{bodies_[2 * k], x + part_x / 2}
                   : std::pair{bodies_[2 * k + 1], x - part_x / 2};
    };
    for (int index = 0; index < kActuators; ++index) {
      const int pair = index % 3;              // j - 1
      const int rear = 2 * pair + 1;           // lump 2j - 1
      const int front = rear + 1;
      if (rear < o.first_lump || front > o.last_lump) continue;
      const double z = index < 3 ? a.top_attach_z_m : a.bottom_attach_z_m;
      const auto [rear_body, rear_x] = attach(rear, a.rear_attach_x_m);
      const auto [front_body, front_x] = attach(front, a.front_attach_x_m);
      actuators_.push_back({index, rear_body, front_body, {rear_x, 0, z}, {front_x, 0, z}});
    }
  }
}

void CaterpillarBody::AddLumpForce(int k, double fx, double fy, double fz) const {
  for (int part = 0; part < parts_; ++part) {
    dBodyAddForce(bodies_[parts_ * k + part], fx / parts_, fy / parts_, fz / parts_);
  }
}

Vec3 CaterpillarBody::Position(int k) const {
  if (parts_ == 1) return FromOde(dBodyGetPosition(bodies_[k]));
  const Vec3 r = FromOde(dBodyGetPosition(bodies_[2 * k]));
  const Vec3 f = FromOde(dBodyGetPosition(bodies_[2 * k + 1]));
  return {(r.x + f.x) / 2, (r.y + f.y) / 2, (r.z + f.z) / 2};
}

Vec3 CaterpillarBody::Velocity(int k) const {
  if (parts_ == 1) return FromOde(dBodyGetLinearVel(bodies_[k]));
  const Vec3 r = FromOde(dBodyGetLinearVel(bodies_[2 * k]));
  const Vec3 f = FromOde(dBodyGetLinearVel(bodies_[2 * k + 1]));
  return {(r.x + f.x) / 2, (r.y + f.y) / 2, (r.z + f.z) / 2};
}

double CaterpillarBody::Pitch(int k) const {
  if (parts_ == 1) return BodyPitch(bodies_[k]);
  const double rear = BodyPitch(bodies_[2 * k]);
  return rear + std::remainder(BodyPitch(bodies_[2 * k + 1]) - rear, 2 * M_PI) / 2;
}

Vec3 CaterpillarBody::Marker(int k) const {
  dVector3 m;
  const double x = params_.markers.offset_x_m + (parts_ == 2 ? body_size_x() / 2 : 0.0);
  dBodyGetRelPointPos(lump(k), x, 0, params_.markers.offset_z_m, m);
  return FromOde(m);
}

void CaterpillarBody::ActuatorState(const ActuatorGeometry& a, Vec3& rear, Vec3& front,
                                    double& length, double& rate) const {
  dVector3 pr, pf, vr, vf;
  dBodyGetRelPointPos(a.rear, a.rear_point.x, a.rear_point.y, a.rear_point.z, pr);
  dBodyGetRelPointPos(a.front, a.front_point.x, a.front_point.y, a.front_point.z, pf);
  dBodyGetRelPointVel(a.rear, a.rear_point.x, a.rear_point.y, a.rear_point.z, vr);
  dBodyGetRelPointVel(a.front, a.front_point.x, a.front_point.y, a.front_point.z, vf);
  const double dx = pf[0] - pr[0], dy = pf[1] - pr[1], dz = pf[2] - pr[2];
  length = std::sqrt(dx * dx + dy * dy + dz * dz);
  rate = ((vf[0] - vr[0]) * dx + (vf[1] - vr[1]) * dy + (vf[2] - vr[2]) * dz) / length;
  rear = FromOde(pr);
  front = FromOde(pf);
}

double CaterpillarBody::Bend(const Link& l) {
  return std::remainder(BodyPitch(l.front) - BodyPitch(l.rear), 2 * M_PI);
}

double CaterpillarBody::LinkBend(int k) const { return Bend(links_[k]); }

// ODE's limit row is J = [axis, -axis] on (rear, front) angular velocity, so the angle it
// expects grows with the rear body's rotation relative to the front: minus the bend.
void CaterpillarBody::UpdateLinkAngles() {
  for (const Link& l : links_) dJointSetAMotorAngle(l.bend, 0, -Bend(l));
  for (const Link& l : inner_links_) dJointSetAMotorAngle(l.bend, 0, -Bend(l));
}

double CaterpillarBody::KineticEnergy() const {
  double e = 0;
  for (dBodyID b : bodies_) {
    dMass m;
    dBodyGetMass(b, &m);
    const dReal* v = dBodyGetLinearVel(b);
    dVector3 w;  // angular velocity in the body frame
    dBodyVectorFromWorld(b, dBodyGetAngularVel(b)[0], dBodyGetAngularVel(b)[1],
                         dBodyGetAngularVel(b)[2], w);
    e += 0.5 * m.mass * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) e += 0.5 * w[r] * m.I[r * 4 + c] * w[c];
    }
  }
  return e;
}

double CaterpillarBody::LinkExtension(int k) const { return AxialExtension(links_[k].axial); }

double CaterpillarBody::PotentialEnergy(double gravity) const {
  double e = 0;
  for (dBodyID b : bodies_) {
    dMass m;
    dBodyGetMass(b, &m);
    e += m.mass * gravity * dBodyGetPosition(b)[2];
  }
  for (const auto* links : {&links_, &inner_links_}) {
    for (const Link& l : *links) {
      const double x = AxialExtension(l.axial), th = Bend(l);
      e += 0.5 * l.axial_k * x * x + 0.5 * l.bending_k * th * th;
    }
  }
  for (const auto& a : actuators_) {
    Vec3 r, f;
    double len, rate;
    ActuatorState(a, r, f, len, rate);
    const double s = len - params_.actuators.min_length_m;
    e += 0.5 * params_.actuators.return_spring_n_per_m * s * s;
  }
  return e;
}

}  // namespace gaitforge::caterpillar
