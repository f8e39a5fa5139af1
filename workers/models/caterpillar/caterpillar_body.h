#pragma once
// The lumped caterpillar in an ODE world (../shared/robots/caterpillar.md): box lumps on a
// line along x, planar links between neighbours, and the geometry of the actuators and
// markers. Stepping (actuator forces, stroke stops, ground contact) is CaterpillarSim's.
//
// A link (i, i+1) is the in-plane part of a prismatic-spherical joint at the midpoint of the
// two centres, as three one-row constraints (a PU joint would add two rows across the plane
// and cost about twice as much per step):
//   shear   rigid: a distance joint (DBall) from the anchor on lump i+1 to a point 1 m above
//           the anchor on lump i keeps the anchors together across lump i's axis;
//   axial   spring-damper: a DBall from lump i's centre to the anchor on lump i+1;
//   bending spring-damper: an angular motor (AMotor, user mode) about y whose stops are set
//           each step from the lumps' relative pitch.
// Nothing acts across the x-z plane and no force has a y component, so y, roll and yaw stay
// exactly zero: lateral and twist are rigid without constraint rows.
//
// The model's resolution (params.effects.lump_compliance_per_mpa > 0): each lump is two
// half-lumps, rear and front, joined at the lump's centre by a link of the same three rows
// whose springs are the silicone block between the halves' centres. A lump's position and
// velocity are then the mean of its halves', its pitch their mean pitch, its marker sits on
// the rear half at the junction, and an actuator attaches to the half that holds its point.
// Links between lumps join the front half of one to the rear half of the next.
#include <ode/ode.h>

#include <array>
#include <vector>

#include "workers/models/caterpillar/caterpillar_params.h"
#include "workers/models/caterpillar/gait.h"

namespace gaitforge::caterpillar {

struct Vec3 {
  double x = 0, y = 0, z = 0;
};

// What to build; the defaults are the whole robot. Element tests build parts of it.
struct BuildOptions {
  int first_lump = 1;      // lumps first..last (1-based, 1..6) are built
  int last_lump = 6;
  bool gravity = true;
  bool ground = true;      // the plane z = 0
  bool actuators = true;   // actuators whose two lumps are built
};

// One actuator: attachment points in the frames of its rear and front lump.
struct ActuatorGeometry {
  int index = 0;           // 0..5 in the order T1 T2 T3 B1 B2 B3
  dBodyID rear = nullptr, front = nullptr;
  Vec3 rear_point, front_point;
};

class CaterpillarBody {
 public:
  // Builds into `world` and `space` (bodies, joints, one box geom per lump).
  CaterpillarBody(dWorldID world, dSpaceID space, const CaterpillarParams& params,
                  const BuildOptions& options, double timestep_s);
  CaterpillarBody(const CaterpillarBody&) = delete;
  CaterpillarBody& operator=(const CaterpillarBody&) = delete;

  int lump_count() const { return static_cast<int>(bodies_.size()) / parts_; }
  // k = 0 .. lump_count()-1 indexes the built lumps (lump first_lump + k); lump(k) is its
  // body, its rear half when the lumps are split.
  dBodyID lump(int k) const { return bodies_[parts_ * k]; }
  // Every ODE body, rear to front (lump_count() of them, or twice that when split), their
  // box geoms, and the share of a lump's mass and length each holds.
  int body_count() const { return static_cast<int>(bodies_.size()); }
  dBodyID body(int i) const { return bodies_[i]; }
  dGeomID geom(int i) const { return geoms_[i]; }
  int parts_per_lump() const { return parts_; }
  double body_size_x() const { return params_.lumps.size_x_m / parts_; }
  // Adds a force at lump k's centre (split between its halves).
  void AddLumpForce(int k, double fx, double fy, double fz) const;
  int link_count() const { return static_cast<int>(links_.size()); }
  // Link k's axial spring-damper row (a DBall; its ERP carries the spring).
  dJointID axial_joint(int k) const { return links_[k].axial; }
  const std::vector<ActuatorGeometry>& actuators() const { return actuators_; }

  Vec3 Position(int k) const;
  Vec3 Velocity(int k) const;
  // Rotation of lump k about +y (rad); +pitch turns +x towards -z (nose down).
  double Pitch(int k) const;
  Vec3 Marker(int k) const;
  // Attachment points in the world frame and the actuator's length (m) and its rate (m/s).
  void ActuatorState(const ActuatorGeometry& a, Vec3& rear, Vec3& front, double& length,
                     double& rate) const;
  // Link k (between lump(k) and lump(k+1)): axial spring extension (m, + when stretched)
  // and bend (rad, pitch of lump k+1 minus pitch of lump k).
  double LinkExtension(int k) const;
  double LinkBend(int k) const;
  // Gives each bending motor its current angle; call before every step.
  void UpdateLinkAngles();

  // Energies (J): kinetic, gravitational (zero at z = 0) and the elastic energy of link and
  // actuator return springs.
  double KineticEnergy() const;
  double PotentialEnergy(double gravity) const;

  // Largest h*omega over the link modes (two-body reduced mass/inertia; inner links too). The spring
  // integration is stable while (h omega)^2 < 4 + 4 zeta h omega: about 0.26 at the
  // canonical 1 ms, so a diverging run with a large value points at the timestep.
  double MaxStepOmega(double timestep_s) const { return timestep_s * max_omega_; }

  const CaterpillarParams& params() const { return params_; }
  const BuildOptions& options() const { return options_; }

 private:
  const CaterpillarParams params_;
  const BuildOptions options_;
  struct Link {
    dJointID shear, axial, bend;
    dBodyID rear, front;
    double axial_k, bending_k;
  };
  // Builds a link between rear and front anchored at x = anchor_x (world, at rest); the
  // axial row runs from the rear body's centre at rear_x to the anchor on the front body.
  Link MakeLink(dWorldID world, dBodyID rear, dBodyID front, double anchor_x, double rear_x,
                const LinkStiffness& k, double c_axial, double c_bend, double h) const;
  // The bend of a link: pitch of its front body minus its rear body's (rad).
  static double Bend(const Link& l);

  int parts_ = 1;                  // bodies per lump: 1, or 2 when split
  std::vector<dBodyID> bodies_;
  std::vector<dGeomID> geoms_;
  std::vector<Link> links_;        // between lumps, rear to front
  std::vector<Link> inner_links_;  // inside split lumps
  std::vector<ActuatorGeometry> actuators_;
  double max_omega_ = 0;
};

}  // namespace gaitforge::caterpillar
