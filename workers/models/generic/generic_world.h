#pragma once
// The generic ODE builder: any descriptor's structure (robots/descriptor.h: bodies, hinge
// joints with springs, dampers and stops, position servos, ground contact) built into its
// own ODE world and stepped. Robot-specific C++ exists only for what cannot be data; this
// class knows no robot.
//
// Per step: the servos' commanded angles pass a first-order lag, each servo is a hinge motor
// whose speed is gain * (command - angle) limited to max_speed, with at most max_torque;
// springs and dampers are explicit torques -k (angle - rest) - c rate; the ground z = 0
// touches every box (Coulomb friction with dContactApprox1, or no slip when the friction
// parameter is infinite); then one dWorldStep and a divergence check.
//
// Planar robots (plane: xz; generic_planar.cc) add spring links (an axial and a bending
// spring-damper as soft constraint rows), pistons (a push along the line between two
// points, a return spring, stroke stops as speculative one-row contacts), ground contacts
// on the boxes' centre-plane corners with friction along x, and self-contacts folded onto
// the plane; per step: joint torques, pistons, effects, servos, ground and self-contacts,
// the links' angles, then the step.
//
// Effects it attaches (workers/effects/effects.h, docs/effects.md), each off at 0: a tether
// pulling the first body backwards (-x) at its centre with F + k max(0, x - x0); gravity
// tilted by a ground slope about y; viscous drag -c v on every body; direction-dependent
// Coulomb friction (forward or backward coefficient by the sign of the body's x velocity,
// 0 keeping the ground's own); a command delay (generic_gait.cc).
#include <array>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>
#include <optional>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"
#include "workers/sim/sim_outcome.h"
#include "workers/models/generic/robot_world.h"
#include "workers/sim/world.h"
#include "workers/learned/mlp.h"

namespace gaitforge::generic {

// Parameter values by name: the descriptor's nominal values with overrides applied, and the
// effects the builder attaches (workers/effects: effect.* of an effect whose part the robot
// has; 0, the effect absent, unless set).
class ParamValues {
 public:
  explicit ParamValues(const robots::RobotDescriptor& d);
  // Sets a parameter, multiplies by a scale ("scale.hinge": each parameter it names must stay
  // in range) or sets an effect's parameter; then checks the descriptor's relations. On
  // error nothing changes and the message names the value and its range (or, for an unknown
  // name, the nearest known ones).
  absl::Status Set(const std::string& name, double value);
  double operator()(const std::string& name) const;
  // An effect parameter's value (0 unless set).
  double Effect(const std::string& name) const;
  // A learned map from the robot's state to some of its parameters (paper 004's adaptive
  // model; docs/learned-models.md): its inputs are channels (a ".rate" suffix: the
  // channel's rate of change), its outputs parameters, which the world sets from it at
  // every step, each held in its range. Checked when the world is built.
  void SetLearned(std::shared_ptr<const learned::Mlp> m) { learned_ = std::move(m); }
  const std::shared_ptr<const learned::Mlp>& learned() const { return learned_; }

 private:
  absl::Status SetScale(const robots::Scale& scale, double factor);
  const robots::RobotDescriptor* d_;
  std::vector<double> values_;  // parallel to d_->parameters
  std::map<std::string, double> effects_;
  std::shared_ptr<const learned::Mlp> learned_;
};

// The builder effects' values (workers/effects: each 0, the effect absent, unless set), read
// once per build by every engine that builds a generic robot.
struct BuilderEffects {
  explicit BuilderEffects(const ParamValues& v);
  double tether_force = 0, tether_stiffness = 0;    // N, N/m on the first body
  double drag = 0;                                  // N s/m on every body
  double friction_forward = 0, friction_backward = 0;
  double contact_slip = 0;                          // m/(N s): ground friction rows' slip
  double slope = 0;                                 // rad, + uphill along +x
  double actuator_lag = 0;    // s: before each servo's own; a piston's push follows it
  double servo_deadband = 0;  // rad
  double piston_deadband = 0;  // N: Coulomb friction along each piston's line
  double spring_softening = 0;  // 1/m: spring links' axial force k x / sqrt(1 + (s x)^2)
  double lump_compliance = 0;   // 1/MPa: bodies of spring links as two deformable halves
  // Bending joints (universal joints with a spring or damper; workers/effects, paper 004's
  // state-dependent P), per axis with deflection psi from rest and rate w:
  double joint_softening = 0;       // 1/rad: spring torque k psi / sqrt(1 + (s psi)^2)
  double joint_damping_growth = 0;  // 1/rad^2: damping c (1 + b psi^2)
  double joint_stiffening = 0;      // s/rad: spring torque times (1 + g |w|)
};

class GenericWorld : public RobotWorld {
 public:
  // Builds the robot at rest; InvalidArgument when its model is not "generic", it has no
  // bodies, or a value makes no physical sense (a non-positive size or mass).
  static absl::StatusOr<std::unique_ptr<GenericWorld>> Build(const robots::RobotDescriptor& d,
                                                             const ParamValues& values,
                                                             double timestep_s);
  GenericWorld(const GenericWorld&) = delete;
  GenericWorld& operator=(const GenericWorld&) = delete;

  // One step with `commands[i]` the angle (rad) commanded to actuator i (descriptor order).
  // !ok once the state diverged (NaN, too fast, too far, ODE error): do not step again.
  // A piston's command is the fraction (0..1) of its force it pushes with; a tendon's its
  // force (N, clamped to its max_force); a missing command is 0.
  sim::SimOutcome Step(const std::vector<double>& commands) override;

  double time() const override { return steps_ * h_; }
  double timestep() const override { return h_; }
  int body_count() const { return static_cast<int>(d_.bodies.size()); }  // the descriptor's
  // The mean of the bodies' centres, mass-weighted (m, world frame).
  std::array<double, 3> CentreOfMass() const override;
  // A hinge's angle, or a universal joint's about its first (axis 1) or second axis (rad).
  double JointAngle(int joint, int axis = 1) const;
  // The value of a recording channel ("hinge.angle", "tip.x"); NotFound for another.
  absl::StatusOr<double> Channel(const std::string& name) const override;
  int ground_contacts() const override { return ground_contacts_; }
  std::array<double, 3> BodyCentre(int body) const override;
  robots::BodyState StateOf(int body) const override;
  double last_piston_work() const override { return piston_work_; }
  const std::vector<double>& piston_extensions() const override { return piston_extensions_; }
  // The largest tilt of the first body (its roll or pitch against the world's level, rad)
  // over the steps so far.
  double max_tilt() const override { return max_tilt_; }
  // Of the servo-steps so far, the fraction in which a servo gave at least 99% of its
  // max_torque (it was stalled by its torque limit); 0 without servos.
  double torque_limited_fraction() const override;
  // The servos' positive mechanical work so far (J): the sum over steps and servos of
  // max(0, torque * joint rate) * h (a servo braking a joint stores nothing).
  double servo_energy() const override { return servo_energy_; }
  const std::vector<double>& actuator_torques() const override { return actuator_torque_; }
  const std::vector<double>& actuator_rates() const override { return actuator_rate_; }
  double total_mass() const override;

  // Inspection (tests, tools): the ODE bodies, rear half first where a body is split
  // (effect.lump_compliance_per_mpa), and how many parts descriptor body `body` was built as.
  int ode_body_count() const { return static_cast<int>(bodies_.size()); }
  dBodyID ode_body(int i) const { return bodies_.at(i); }
  int parts(int body) const { return built_.at(body).parts; }
  // A spring link's (descriptor joint `joint`) axial extension beyond its rest length (m)
  // and its bend (rad, body 2's pitch less body 1's) now; 0 for another joint.
  double LinkExtension(int joint) const;
  double LinkBend(int joint) const;

 private:
  GenericWorld(const robots::RobotDescriptor& d, const ParamValues& v, double timestep_s);
  absl::Status BuildBodies(const ParamValues& v);
  absl::Status BuildJoints(const ParamValues& v);
  dJointID BuildUniversal(const robots::Joint& j, dBodyID b1, dBodyID b2, const ParamValues& v);
  absl::Status BuildActuators(const ParamValues& v);
  void BuildMarkers(const ParamValues& v);
  absl::Status BuildSpringLink(const robots::Joint& j, const ParamValues& v);
  // A spring link's rows between b1 and b2: the axial spring from b1's point p1 to b2's
  // point at the anchor, along `axis` (world frame, at rest), stiffnesses k (N/m) and kappa
  // (N m/rad), dampers c (N s/m) and c_bend (N m s/rad).
  void AddLink(dBodyID b1, dBodyID b2, const std::array<double, 3>& anchor,
               const std::array<double, 3>& axis, const std::array<double, 3>& p1, double k,
               double kappa, double c, double c_bend);
  // Resolution (effect.lump_compliance_per_mpa; generic_resolution.cc): a body a spring link
  // joins is built as two halves along its x axis, joined at its centre by the block of
  // material between them (a spring link: axial E A / l, bending E I / l, l its half
  // length, damped like the body's first spring link), unless the block is too stiff for
  // the timestep.
  struct Split {
    bool on = false;
    double k = 0, kappa = 0, zeta = 0, zeta_bend = 0;
  };
  Split SplitOf(int body, const std::array<double, 3>& size, double mass,
                const ParamValues& v) const;
  // A box of the given lengths, or with `sphere` a sphere of diameter size[0].
  void CreateBody(const std::string& name, const std::array<double, 3>& size, double mass,
                  const std::array<double, 3>& pos, const dReal* rotation, bool sphere = false);
  absl::Status BuildBody(int index, const ParamValues& v);
  // The built body of descriptor body `body` nearest a world point (its half, if split),
  // and a point of its frame in the frame of the half that holds it (x <= 0: the rear).
  int NearPart(int body, const std::array<double, 3>& world) const;
  std::pair<int, std::array<double, 3>> Locate(int body, std::array<double, 3> point) const;
  int BodyIndex(const std::string& name) const;  // in the descriptor; -1: the world
  absl::Status BuildPiston(const robots::Actuator& a, int index, const ParamValues& v);
  absl::Status BuildTendon(const robots::Actuator& a, int index, const ParamValues& v);
  void ApplyTendons(const std::vector<double>& commands);
  void ApplyJointTorques();
  void ApplyPistons(const std::vector<double>& commands);
  void AddPlanarGroundContacts();
  void AddSelfContacts();
  void UpdateLinkAngles();
  void MeasurePistons();
  sim::SimOutcome CheckPistons() const;
  void ApplyEffects();
  // The learned parameter map (ParamValues::learned; generic_learned.cc): checked at build,
  // applied before every step's joint torques.
  absl::Status BuildLearned(const ParamValues& v);
  void ApplyLearned();
  struct Learned {
    std::shared_ptr<const learned::Mlp> mlp;
    std::vector<std::string> channels;  // per input, without ".rate"
    std::vector<bool> rate;             // per input: the channel's rate of change
    std::vector<double> previous;       // the channels' values at the last step
    std::vector<const robots::Parameter*> outputs;
    std::unique_ptr<ParamValues> values;  // the build's values with the outputs set
  };
  std::optional<Learned> learned_;
  void ApplyServos(const std::vector<double>& commands);
  void AddGroundContacts();
  sim::SimOutcome CheckState();
  void Observe();  // after a step: tilt and servo torques

  struct Spring {
    double k = 0, c = 0, rest = 0;
    double k2 = 0, c2 = 0, rest2 = 0;  // a universal joint's second axis
  };
  static Spring SpringOf(const robots::Joint& j, const ParamValues& v);
  void AddUniversalSpring(dJointID j, const Spring& s);
  double SpringTorque(double k, double psi, double rate) const;
  void AddUniversalDamper(dJointID u, const Spring& s);
  void UpdateUniversalDampers();
  struct UniversalDamper {
    dJointID joint, motor;
    double c1, c2, rest1, rest2;  // the descriptor's damping per axis, and the rest angles
  };
  std::vector<UniversalDamper> universal_dampers_;
  static double UniversalAngle(dJointID j, int axis);
  // A spring link's three rows: a shear row (a distance held between a point far above
  // the anchor on body 1 and the anchor on body 2), the axial spring and the bend spring
  // (a one-axis angular motor whose equal stops make a two-sided soft row).
  struct Link {
    dJointID shear = nullptr, axial = nullptr, bend = nullptr;
    dBodyID b1 = nullptr, b2 = nullptr;
    double axial_erp = 0;  // the linear axial spring's ERP (h k / c)
  };
  void SoftenLinks();
  static double Bend(const Link& l);
  // A fraction zeta of critical damping, c = 2 zeta sqrt(k mu), for two bodies joined by a
  // spring, mu their reduced mass (or inertia) a b / (a + b); the exact half for equal bodies.
  static double Damping(double zeta, double k, double a, double b);
  struct Piston {
    int actuator = 0;  // its index in the descriptor's actuators (and commands)
    dBodyID b1 = nullptr, b2 = nullptr;
    std::array<double, 3> p1{}, p2{};  // attachment points, body frames
    double force = 0, k = 0, min = 0, max = 0, stop_erp = 0, stop_cfm = 0, tolerance = 0;
    double lighter_mass = 0;  // of its two bodies: sizes the stops' look-ahead margin
    double push = 0;          // effect.actuator_lag_s: the lagged push (N), from 0 at rest
  };
  // A piston's two points, its length and the rate of its length now.
  struct PistonState {
    std::array<double, 3> r{}, f{};
    double length = 0, rate = 0;
  };
  static PistonState StateOf(const Piston& p);
  void AddPistonDeadband(const Piston& p, const PistonState& s, double ux, double uy, double uz);
  struct Servo {
    int actuator = 0;  // its index in the descriptor's actuators (and commands)
    int joint = 0;
    double gain = 0, max_speed = 0, max_torque = 0, lag_keep = 0;
    // A PD servo (kp, kd): an explicit torque, the last one applied kept for its power.
    bool pd = false;
    double kp = 0, kd = 0, torque = 0;
    // effect.actuator_lag_s: a further lag in series, before the servo's own (0: none).
    double extra_keep = 0;
    double extra = 0;    // the command after the effect's lag (rad)
    double command = 0;  // the lagged command (rad)
    bool started = false;
  };
  const robots::RobotDescriptor& d_;
  const double h_;
  sim::World world_;
  // Per descriptor body: its first ODE body, how many (2 when split), the halves' offset
  // from its centre along its x axis (m), that axis and its centre at the start.
  struct Built {
    int first = 0, parts = 1;
    double half_x = 0;
    double mass = 0, inertia_y = 0;  // the whole body's (kg, kg m^2 about its y)
    std::array<double, 3> axis{1, 0, 0}, centre{};
  };
  std::vector<Built> built_;
  std::vector<Split> splits_;             // per descriptor body
  std::vector<std::string> body_names_;  // per ODE body, for messages
  std::vector<dBodyID> bodies_;           // ODE bodies, rear half first where split
  std::vector<dGeomID> geoms_;
  std::vector<double> masses_;
  std::vector<std::array<double, 3>> sizes_;  // box lengths, body frame (m; a sphere: 2r)
  std::vector<double> radius_;                 // a sphere's radius (m); 0 for a box
  // Per body: its ground friction coefficient (the ground's unless it gives its own) and
  // the overlap it may keep (m).
  std::vector<double> body_friction_, contact_depth_;
  std::vector<std::array<double, 3>> start_;
  std::vector<dJointID> joints_;
  std::vector<Spring> springs_;
  std::vector<Servo> servos_;
  std::vector<Link> links_;
  std::vector<int> joint_link_;  // per descriptor joint: its index in links_, or -1
  std::vector<Piston> pistons_;
  // A tendon (generic_tendons.cc): its force, clamped to +-max (N), turns body `end` by
  // `arm` (N m per N, its frame) and `base` (nullptr: the world) the other way.
  struct Tendon {
    int actuator = 0;
    dBodyID base = nullptr, end = nullptr;
    std::array<double, 3> arm{};
    double max = 0;
  };
  std::vector<Tendon> tendons_;
  std::vector<double> piston_lengths_;  // after the last step
  std::vector<double> piston_extensions_;  // length - min_length, after the last step
  double piston_work_ = 0;  // in the last step
  // Self-contact: the pairs of bodies (i < j) that no joint joins, in order, and the
  // squared distance of their centres beyond which they cannot touch (their half-diagonals
  // together).
  struct ContactPair {
    int i = 0, j = 0;
    double reach2 = 0;
  };
  std::vector<ContactPair> contact_pairs_;
  struct Marker {
    std::string name;
    int body = 0;
    std::array<double, 3> offset{};  // body frame
  };
  std::vector<Marker> markers_;
  double friction_ = 0, contact_erp_ = 0, contact_cfm_ = 0;
  // friction_load "body": each body's normal load on the ground in the last step (N), read
  // from its contacts' feedback (kMaxContacts per body, stable addresses).
  bool body_load_ = false;
  static constexpr int kMaxContacts = 8;
  std::vector<double> load_;
  std::vector<dJointFeedback> contact_feedback_;
  std::vector<int> contact_count_;
  BuilderEffects fx_;
  double max_speed_ = 0, max_excursion_ = 0;
  int64_t steps_ = 0;
  int ground_contacts_ = 0;
  // The servos' joint reactions (ODE writes them each step; stable addresses: a deque).
  std::deque<dJointFeedback> feedback_;
  double max_tilt_ = 0;
  int64_t torque_limited_ = 0;
  double servo_energy_ = 0;
  std::vector<double> actuator_torque_, actuator_rate_;  // per actuator, the last step's
};

}  // namespace gaitforge::generic
