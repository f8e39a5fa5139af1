#include "workers/models/caterpillar/caterpillar_body.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

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

}  // namespace

CaterpillarBody::CaterpillarBody(dWorldID world, dSpaceID space, const CaterpillarParams& p,
                                 const BuildOptions& o, double h)
    : params_(p), options_(o) {
  if (o.first_lump < 1 || o.last_lump > 6 || o.first_lump > o.last_lump) {
    throw std::invalid_argument("BuildOptions: lumps must satisfy 1 <= first <= last <= 6");
  }
  const auto& L = p.lumps;
  const double z0 = L.size_z_m / 2;
  dMass mass;
  dMassSetBoxTotal(&mass, L.mass_kg, L.size_x_m, L.size_y_m, L.size_z_m);
  const double inertia_yy = mass.I[1 * 4 + 1];

  for (int i = o.first_lump; i <= o.last_lump; ++i) {
    dBodyID b = dBodyCreate(world);
    dBodySetPosition(b, (i - 1) * L.spacing_m, 0, z0);
    dBodySetMass(b, &mass);
    lumps_.push_back(b);
    dGeomID g = dCreateBox(space, L.size_x_m, L.size_y_m, L.size_z_m);
    dGeomSetBody(g, b);
    geoms_.push_back(g);
  }

  for (int k = 0; k + 1 < lump_count(); ++k) {
    const int i = o.first_lump + k;  // link (i, i+1)
    const LinkStiffness& s = p.Link(i);
    dBodyID rear = lumps_[k], front = lumps_[k + 1];
    const double ax = (i - 0.5) * L.spacing_m;  // anchor, world frame at rest
    // Critical damping for the two-lump system (paper): reduced mass m/2, inertia I_yy/2.
    const double c_axial =
        2 * p.links.axial_damping_ratio * std::sqrt(s.axial_n_per_m * L.mass_kg / 2);
    const double c_bend =
        2 * p.links.bending_damping_ratio * std::sqrt(s.bending_nm_per_rad * inertia_yy / 2);
    Link link;
    link.shear = dJointCreateDBall(world, nullptr);
    dJointAttach(link.shear, rear, front);
    dJointSetDBallAnchor1(link.shear, ax, 0, z0 + kShearLeverM);
    dJointSetDBallAnchor2(link.shear, ax, 0, z0);
    dJointSetDBallParam(link.shear, dParamERP, p.simulation.solver_erp);
    dJointSetDBallParam(link.shear, dParamCFM, p.simulation.solver_cfm);

    link.axial = dJointCreateDBall(world, nullptr);
    dJointAttach(link.axial, rear, front);
    dJointSetDBallAnchor1(link.axial, ax - L.spacing_m / 2, 0, z0);
    dJointSetDBallAnchor2(link.axial, ax, 0, z0);
    const SoftRow axial = SpringDamper(s.axial_n_per_m, c_axial, h);
    dJointSetDBallParam(link.axial, dParamERP, axial.erp);
    dJointSetDBallParam(link.axial, dParamCFM, axial.cfm);

    link.bend = dJointCreateAMotor(world, nullptr);
    dJointAttach(link.bend, rear, front);
    dJointSetAMotorMode(link.bend, dAMotorUser);
    dJointSetAMotorNumAxes(link.bend, 1);
    dJointSetAMotorAxis(link.bend, 0, 1, 0, 1, 0);  // y, fixed in the rear lump
    const SoftRow bend = SpringDamper(s.bending_nm_per_rad, c_bend, h);
    dJointSetAMotorParam(link.bend, dParamHiStop, 0);
    dJointSetAMotorParam(link.bend, dParamLoStop, 0);  // lo = hi: a two-sided row
    dJointSetAMotorParam(link.bend, dParamStopERP, bend.erp);
    dJointSetAMotorParam(link.bend, dParamStopCFM, bend.cfm);
    dJointSetAMotorAngle(link.bend, 0, 0);

    links_.push_back(link);
    link_axial_k_.push_back(s.axial_n_per_m);
    link_bending_k_.push_back(s.bending_nm_per_rad);
    max_omega_ = std::max({max_omega_, std::sqrt(s.axial_n_per_m / (L.mass_kg / 2)),
                           std::sqrt(s.bending_nm_per_rad / (inertia_yy / 2))});
  }

  if (o.actuators) {
    const auto& a = p.actuators;
    for (int index = 0; index < kActuators; ++index) {
      const int pair = index % 3;              // j - 1
      const int rear = 2 * pair + 1;           // lump 2j - 1
      const int front = rear + 1;
      if (rear < o.first_lump || front > o.last_lump) continue;
      const double z = index < 3 ? a.top_attach_z_m : a.bottom_attach_z_m;
      actuators_.push_back({index, lumps_[rear - o.first_lump], lumps_[front - o.first_lump],
                            {a.rear_attach_x_m, 0, z}, {a.front_attach_x_m, 0, z}});
    }
  }
}

Vec3 CaterpillarBody::Position(int k) const { return FromOde(dBodyGetPosition(lumps_[k])); }
Vec3 CaterpillarBody::Velocity(int k) const { return FromOde(dBodyGetLinearVel(lumps_[k])); }

double CaterpillarBody::Pitch(int k) const {
  const dReal* r = dBodyGetRotation(lumps_[k]);  // 3x4 row-major; column 0 is body x
  return std::atan2(-r[8], r[0]);
}

Vec3 CaterpillarBody::Marker(int k) const {
  dVector3 m;
  dBodyGetRelPointPos(lumps_[k], params_.markers.offset_x_m, 0, params_.markers.offset_z_m, m);
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

double CaterpillarBody::LinkExtension(int k) const {
  dVector3 a1, a2;
  dJointGetDBallAnchor1(links_[k].axial, a1);
  dJointGetDBallAnchor2(links_[k].axial, a2);
  return std::sqrt((a2[0] - a1[0]) * (a2[0] - a1[0]) + (a2[1] - a1[1]) * (a2[1] - a1[1]) +
                   (a2[2] - a1[2]) * (a2[2] - a1[2])) -
         dJointGetDBallDistance(links_[k].axial);
}

double CaterpillarBody::LinkBend(int k) const {
  return std::remainder(Pitch(k + 1) - Pitch(k), 2 * M_PI);
}

// ODE's limit row is J = [axis, -axis] on (rear, front) angular velocity, so the angle it
// expects grows with the rear lump's rotation relative to the front: minus the bend.
void CaterpillarBody::UpdateLinkAngles() {
  double pitch[6];
  for (int k = 0; k < lump_count(); ++k) pitch[k] = Pitch(k);
  for (int k = 0; k < link_count(); ++k) {
    dJointSetAMotorAngle(links_[k].bend, 0, -std::remainder(pitch[k + 1] - pitch[k], 2 * M_PI));
  }
}

double CaterpillarBody::KineticEnergy() const {
  double e = 0;
  for (dBodyID b : lumps_) {
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

double CaterpillarBody::PotentialEnergy(double gravity) const {
  double e = 0;
  for (dBodyID b : lumps_) e += params_.lumps.mass_kg * gravity * dBodyGetPosition(b)[2];
  for (int k = 0; k < link_count(); ++k) {
    const double x = LinkExtension(k), th = LinkBend(k);
    e += 0.5 * link_axial_k_[k] * x * x + 0.5 * link_bending_k_[k] * th * th;
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
