#pragma once
// A robot as data (docs/robots.md): everything a robot is and offers, each fact written once,
// read from robots/<name>/robot.yaml by ParseDescriptor (descriptor_parser.h). This is the
// compiled, read-only form that the rest of gaitforge reads: the parameters with their
// units, ranges and nominal values, the relations between them, the controller and its gene
// space, and the sensors that become recording channels.
//
// Free of ODE, gRPC, Protobuf and SQLite: at the bottom of the dependency graph.
#include <array>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "robots/expr.h"

namespace gaitforge::robots {

// Where a value was written: file, 1-based line and column (0 when unknown).
struct Mark {
  std::string source;
  int line = 0;
  int column = 0;
  // "robot.yaml:12:5", or just the source when the line is unknown.
  std::string ToString() const;
};

// One number of the robot.
struct Parameter {
  std::string name;   // dotted, e.g. "lumps.mass_kg"
  double value = 0;   // nominal; +infinity only where `infinite` is set
  double lo = 0, hi = 0;  // closed range of finite values
  std::string unit;   // "" when dimensionless
  std::string doc;
  bool integer = false;       // whole numbers only
  bool calibratable = false;  // a calibration study may set it by name
  std::string infinite;       // non-empty: the value may be infinite, which means this
  Mark mark;                  // where its value is written

  // "[0.001, 1] kg" (with " or infinite" where allowed).
  std::string RangeText() const;
  // "" when `v` is allowed; otherwise "NAME = V UNIT is outside RANGE".
  std::string Check(double v) const;
};

// A factor that multiplies several parameters at once ("scale.link_stiffness").
struct Scale {
  std::string name;  // with its "scale." prefix
  std::string doc;
  std::vector<std::string> multiplies;  // parameter names
};

// A model error the robot's authors suspect (`suspects:`; docs/robots.md): one or more of its
// calibratable parameters or scales that may be set wrong, with the range a fit may search.
// The gap finder tries it beside the effect catalog's entries (workers/effects/).
struct Suspect {
  std::string id;          // "knee.hind_stiffness"; not a catalog effect's id
  std::string name;        // short human name
  std::string meaning;     // what may be wrong, and why it is suspected
  std::string where;       // the residual pattern it would leave
  std::string experiment;  // an experiment that settles it
  struct Fit {
    std::string name;       // a calibratable parameter or a scale ("scale.x")
    double lo = 0, hi = 0;  // the range a fit searches
    double nominal = 0;     // the model as it is: the parameter's value, 1 for a scale
    std::string unit;
  };
  std::vector<Fit> fit;
  Mark mark;
};

// Physics the robot's build rules out (`ruled_out:`; docs/robots.md): a catalog effect the
// gap finder then neither tries by default nor accepts as a candidate, with the reason (a
// battery on board rules out a tether). Its id is checked against the catalog when a
// diagnosis is validated (services/diagnosis/spec.cc).
struct RuledOut {
  std::string id;   // "tether.constant"
  std::string why;  // "battery on board (fact sheet: 45 g with the battery)"
  Mark mark;
};

// A linear relation between parameters that must hold: sum(lhs) OP sum(rhs), each side a
// signed sum of parameter names, OP one of < <= > >=.
struct Relation {
  struct Term {
    double sign = 1;
    std::string name;
  };
  std::vector<Term> lhs, rhs;
  std::string op;    // "<", "<=", ">", ">="
  std::string text;  // as written
  std::string why;   // what it protects, for messages
  Mark mark;
};

struct Gene {
  std::string name;
  double lo = 0, hi = 0;
  // A phase: lo and hi are the same point of a cycle (hi - lo = 1 cycle), so engines wrap
  // it instead of reflecting it, and gaits equal up to one shift of all phases are one gait.
  bool circular = false;
};

// The robot's controller: its kind (robots/controllers.h) and what the kind needs.
struct Controller {
  std::string kind;                    // e.g. "phase_onoff"
  std::vector<std::string> actuators;  // the actuators it drives, in gene order
  // The kind's ranges by key (phase_onoff: period_s; sine: frequency_hz, amplitude_rad,
  // offset_rad), each [lo, hi].
  std::map<std::string, std::array<double, 2>> ranges;
  // The kind's numbers by key (leg_gait: thigh_m, calf_m, ...), at nominal values.
  std::map<std::string, double> values;
  std::vector<Gene> genes;             // derived from the kind; the gene space
};

// The structure a generic model builds (model: generic; docs/robots.md, "Structure"). Every
// number is an Expr of the parameters, so a calibration that changes a parameter changes
// the body built from it.
using Vec3Expr = std::array<Expr, 3>;

// A sensor group, which becomes recording channels.
struct Sensor {
  std::string kind;  // "marker" (a point's position), "joint_angle", "joint_torque" (a servo's
                     // torque) or "joint_rate" (its joint's rate)
  std::vector<std::string> names;   // markers rear to front, or joint names
  std::vector<std::string> axes;    // marker: a subset of x, y, z
  std::string spacing;              // marker: parameter with their rest spacing along x
  // marker, generic model: the body each marker is on (parallel to names), and the point
  // in that body's frame (m, default its centre).
  std::vector<std::string> bodies;
  std::optional<Vec3Expr> offset;
};


struct Body {
  std::string name;
  std::string shape;  // "box" or "sphere"
  Vec3Expr size;      // m, full lengths along the body's x, y, z (a sphere: 2r each)
  Expr mass;          // kg, uniform density
  Vec3Expr position;  // m, world frame, at the start
  std::optional<Expr> pitch;  // rad about +y at the start (+: the body's +x tips down)
  // Its own ground contact, where it differs from ground's: Coulomb coefficient, and the
  // overlap with the ground it may keep before it touches (m; the intent of Gazebo's
  // min_depth, paper 003's d: the foot rests that deep, without friction in the layer).
  std::optional<Expr> friction, contact_depth;
  Mark mark;
};

// The body name a joint uses for the fixed world frame (a robot's base bolted down).
inline constexpr const char* kWorldBody = "world";

struct Joint {
  std::string name;
  // "hinge"; "universal": two axes, `axis` fixed in body1 and `axis2` in body2 (a bend in
  // two directions, as a continuum arm's lumps); "fixed": welded as built, no other field;
  // "spring_link": a planar robot's compliant link (plane: xz), which stretches along
  // `axis` and bends about y, each a spring-damper (docs/robots.md).
  std::string type;
  std::string body1, body2;     // body names; body2 turns relative to body1 (body1 may be kWorldBody)
  Vec3Expr anchor;              // m, world frame at the start
  std::array<double, 3> axis{}; // unit vector, world frame at the start
  std::array<double, 3> axis2{};  // universal: the second axis, perpendicular to axis
  std::optional<Expr> stiffness, damping, rest;  // N m/rad, N m s/rad, rad (about axis)
  std::optional<Expr> stiffness2, damping2, rest2;  // universal: about axis2
  std::optional<Expr> lo, hi;   // stops, rad (hinge only)
  std::optional<Expr> friction;  // Coulomb friction torque, N m (hinge only): up to this much
                                 // opposes the joint's turning, and holds it below that
  // spring_link: the axial spring (N/m) runs from body1's point at anchor - length * axis
  // to body2's point at the anchor (length in m); `stiffness` is the bending spring, and
  // both dampers are fractions of critical damping for the two bodies (axial_damping_ratio,
  // damping_ratio).
  std::optional<Expr> axial_stiffness, axial_damping_ratio, damping_ratio, length;
  Mark mark;
  // Its angle channels' suffixes: "angle" for a hinge, "angle1" and "angle2" for a
  // universal joint, none for a fixed one.
  std::vector<std::string> AngleFields() const;
};

struct Actuator {
  std::string name;
  // "servo": position control of a hinge; "piston": a force along the line between two
  // bodies' points, with a return spring and stroke stops; "tendon": a rod fixed to a
  // distal body and pulled from a proximal one (docs/robots.md).
  std::string type;
  std::string joint;
  // servo: speed command gain (1/s) on the angle error, speed limit (rad/s), torque limit
  // (N m) and first-order lag of the commanded angle (s, 0 = none).
  Expr gain, max_speed, max_torque, lag_s;
  // servo, PD instead of a speed command: the torque kp (command - angle) - kd rate (N m/rad,
  // N m s/rad), at most max_torque either way (a torque-controlled joint, paper 002's Go2).
  std::optional<Expr> kp, kd;
  // piston: between body1's point attach1 and body2's point attach2 (body frames, m); the
  // command (0..1) times `force` (N) pushes them apart; the return spring (N/m) pulls with
  // zero force at min_length; stops hold the length in [min_length, max_length] (m) with
  // stop_erp and stop_cfm; a length beyond them by overrun_tolerance (m) has diverged.
  std::string body1, body2;
  Vec3Expr attach1, attach2;
  Expr force, return_stiffness, min_length, max_length, stop_erp, stop_cfm, overrun_tolerance;
  // tendon: a rod from body1 (the base, or the world) to its end on body2 at attach2 (body
  // frame, m from body2's backbone), pulling body2 along `pull` (body2's frame) with the
  // command's force (N, signed: a rod pushes too), at most max_force (N) either way. The
  // rod's tension is carried by the backbone, so what the tendon does is a moment,
  // attach2 x pull f, on body2 and its opposite on body1 (paper 004's T = B f).
  Vec3Expr pull;
  Expr max_force;
  Mark mark;
  // The recording column that drives this actuator under a "playback" command
  // (docs/recording-format.md) and its unit: a tendon's force "<name>.force" (N), a servo's
  // set-point "<name>.setpoint" (rad), a piston's share of its force "<name>.on" (0..1).
  std::string InputChannel() const;
  std::string InputUnit() const;
};

// Ground contact: the plane z = 0 under every body.
struct Ground {
  Expr friction;  // Coulomb coefficient; its parameter may be infinite (no slip)
  Expr erp, cfm;  // contact softness (ODE's ERP and CFM)
  // Friction acts at a box's deepest touching corner, bounded by the coefficient times
  // "corner": that corner's own normal force; "body": the box's whole normal load on the
  // ground in the step before (Coulomb's law for the box; docs/robots.md).
  std::string friction_load = "corner";
};

// Tracking a path with a marker (`tracking:`; docs/robots.md, "Tracking"): paper 004's
// kinematic PID. Each control tick the marker's error e (reference minus position, on
// `axes`) becomes every tendon's rod-length error dl_k = (a_k . e) / lever, a_k the rod's
// attach point on its distal body, and a PID on dl_k gives the rod's force change (N). Only
// tendon actuators are steered; a model's feed-forward (workers/models/generic/
// generic_tracking.h) adds to it.
struct Tracking {
  std::string marker;     // a marker sensor's name
  std::vector<int> axes;  // 0 x, 1 y, 2 z: the axes steered and measured, in order
  Expr lever;             // m the marker moves per radian of bend (> 0)
  Expr kp, ki, kd;        // N/m, N/(m s), N s/m on each rod's length error
  Expr rate_hz;           // the control loop's rate
  Expr lead_s;            // s from rest to the path's start, the reference eased there
  Mark mark;
};

// What the motors draw from the battery (`electrical:`; docs/robots.md, "Electrical"):
// paper 002's cost of transport. Each motor type drives some servo actuators through a
// gear; a joint's torque tau and rate w give the rotor's q-axis current i = tau / (gear kt)
// and the electrical power tau w + 1.5 resistance i^2 (a three-phase motor, amplitude-
// invariant currents). The bus adds the standby current's power; braking power (< 0) returns
// to the battery times regen_efficiency.
struct Electrical {
  struct Motor {
    std::vector<std::string> actuators;  // servo actuators it drives
    Expr gear;                           // rotor turns per joint turn (>= 1)
    Expr kt;                             // torque constant at the rotor (N m/A, > 0)
    Expr resistance;                     // winding resistance per phase (ohm, >= 0)
  };
  std::vector<Motor> motors;
  Expr bus_voltage;       // V (> 0)
  Expr standby_current;   // A (>= 0)
  Expr regen_efficiency;  // 0..1
  // A learned current model (a gaitforge.mlp.v1 file: inputs "<servo>.torque" and
  // "<servo>.rate", output "bus.current" in A) that replaces the motors' model: the bus
  // draws bus_voltage times its output. "": none. A file of the built-in robot of the
  // descriptor's name (robots/<name>/), else a path beside the descriptor's file.
  std::string current_model;
  // The rate of the recordings it learned from (Hz, > 0): the meter asks it for the current
  // that often in simulated time and holds the answer between (paper 002: 500 Hz).
  Expr current_model_rate_hz;
  Mark mark;
};

// The report figure kinds a descriptor may offer (`figures:`; docs/robots.md):
// paper_gait: gait diagrams, period sweep and travelling waves of the best gaits and the
// best one's markers (paper 000's figures, drawn with gaitforge-sim's tools).
inline const std::vector<std::string> kFigureKinds = {"paper_gait"};

struct RobotDescriptor {
  std::string name;     // "caterpillar"
  std::string summary;
  std::string paper;    // the paper it follows (../shared/papers/), may be empty
  std::string model;    // the model kind that simulates it (workers/)
  // Report figures its model's tools can draw for a gait study (kFigureKinds), beyond the
  // fitness curve every study gets; empty: none.
  std::vector<std::string> figures;
  // Its counts (`counts:`: how many of a repeated part, such as the arm's lumps), each a
  // whole number within its range, used as $name in the descriptor's texts (templates.h).
  struct Count {
    std::string name, doc;
    int value = 0, lo = 0, hi = 0;
  };
  std::vector<Count> counts;
  // Its own names for robot.distance and robot.calibration bound to it (`objectives:`), the
  // names its paper's studies use (the caterpillar: caterpillar.distance); empty: none.
  std::string distance_objective, calibration_objective;
  std::string source;   // the file it was read from, for messages
  std::vector<Parameter> parameters;
  std::vector<Scale> scales;
  std::vector<Suspect> suspects;
  std::vector<RuledOut> ruled_out;
  std::vector<Relation> relations;
  Controller controller;
  std::vector<Sensor> sensors;
  std::vector<Body> bodies;
  std::vector<Joint> joints;
  std::vector<Actuator> actuators;
  std::optional<Ground> ground;
  // "xz": a planar robot, moving in the x-z plane (symmetric about it): its ground contacts
  // sit on the boxes' centre-plane corners with friction along x only, its self-contacts
  // are folded onto the plane. "": a 3-D robot.
  std::string plane;
  // Bodies not joined by a joint touch each other (frictionless); off: they pass through.
  bool self_contact = false;
  std::optional<Tracking> tracking;  // none: the robot does not track paths
  std::optional<Electrical> electrical;  // none: no electrical power or cost of transport

  const Parameter* FindParameter(std::string_view name) const;
  const Scale* FindScale(std::string_view name) const;
  const Body* FindBody(std::string_view name) const;
  const Joint* FindJoint(std::string_view name) const;
  // The parameter's nominal value; throws std::out_of_range when the robot lacks it.
  double Value(std::string_view name) const;
  // Names a calibration may set: calibratable parameters in file order, then the scales.
  std::vector<std::string> CalibratableNames() const;
  // The recording channels besides "t": "m1.x", ..., "knee_l.angle", in sensor order.
  std::vector<std::string> Channels() const;
  // Every actuator's input channel (Actuator::InputChannel), in descriptor order.
  std::vector<std::string> InputChannels() const;
  // Markers (rear to front) and their rest spacing (m); 0 and 0 when it has none.
  int MarkerCount() const;
  double MarkerSpacing() const;
  // Checks every relation with parameter values from `value_of`; the error names the
  // relation, its two sides' values and why it must hold.
  absl::Status CheckRelations(const std::function<double(const std::string&)>& value_of) const;
};

// The up to three names of `known` nearest to `name` (edit distance), for "did you mean".
std::vector<std::string> Nearest(std::string_view name, const std::vector<std::string>& known,
                                 size_t count = 3);

}  // namespace gaitforge::robots
