#pragma once
// Every number of the lumped caterpillar model (../shared/robots/caterpillar.md), as read
// from its descriptor robots/caterpillar/robot.yaml, which holds each value with its unit
// and range (docs/robots.md). SI units throughout.
#include <string>
#include <string_view>

#include "absl/status/statusor.h"
#include "robots/descriptor.h"

namespace gaitforge::caterpillar {

struct LinkStiffness {
  double axial_n_per_m = 0;        // along the body
  double bending_nm_per_rad = 0;   // about y
};

struct CaterpillarParams {
  struct Lumps {
    double mass_kg = 0;
    double size_x_m = 0, size_y_m = 0, size_z_m = 0;
    double spacing_m = 0;
  } lumps;
  struct Links {
    LinkStiffness flexure;   // links (1,2) (3,4) (5,6)
    LinkStiffness segment;   // links (2,3) (4,5)
    double axial_damping_ratio = 0;    // fraction of critical for the two-lump system
    double bending_damping_ratio = 0;
  } links;
  struct Actuators {
    double force_n = 0;
    double return_spring_n_per_m = 0;  // zero force at min_length_m
    double min_length_m = 0, max_length_m = 0;
    double rear_attach_x_m = 0, front_attach_x_m = 0;
    double top_attach_z_m = 0, bottom_attach_z_m = 0;
    double stop_erp = 0, stop_cfm = 0;
    double overrun_tolerance_m = 0;
  } actuators;
  struct Ground {
    bool infinite_friction = true;
    double friction_coefficient = 0;   // used when !infinite_friction
    double contact_erp = 0, contact_cfm = 0;
  } ground;
  struct Markers {
    double offset_x_m = 0, offset_z_m = 0;
  } markers;
  struct Simulation {
    double gravity_m_per_s2 = 0;
    double timestep_s = 0;
    int settle_cycles = 0;
    int measured_cycles = 0;
    double solver_erp = 0, solver_cfm = 0;
    double max_speed_m_per_s = 0;
    double max_excursion_m = 0;
  } simulation;
  // Candidate physical effects beyond the paper's model (issue 8; the catalog with their
  // meaning and fit ranges: workers/effects/effects.h). The descriptor's effect.* values
  // are zero, which is OFF and leaves every result bit-identical to the model without
  // them; calibration sets them by name (param_overrides.h, "effect.*").
  struct Effects {
    // A constant force pulling the rear lump (lump 1) backwards (-x), at its centre: the
    // pneumatic hoses trailing behind the robot (paper 000). N, >= 0.
    double tether_force_n = 0;
    // An extra backward pull on lump 1 growing with its forward travel from its start x0:
    // F = k max(0, x - x0) (hoses drawn out as the robot moves away). N/m, >= 0.
    double tether_stiffness_n_per_m = 0;
    // Ground slope about y: gravity tilted to (-g sin s, 0, -g cos s) in the ground frame,
    // so positive s means uphill when moving +x. rad, |s| <= 0.3.
    double slope_rad = 0;
    // Viscous drag on every lump, F = -c v (x and z components, explicit). N s/m, >= 0.
    double drag_n_s_per_m = 0;
    // Finite Coulomb friction coefficients for a lump sliding forward / backward. 0 means
    // "as the model is" (ground.friction: infinite unless a coefficient is set). When either
    // is > 0, a lump's ground contact uses dContactApprox1 with the coefficient chosen by
    // the sign of the lump's x velocity at the start of the step (forward if v_x >= 0);
    // a direction left at 0 keeps the model's ground friction.
    double friction_forward = 0, friction_backward = 0;
    // First-order lag of each actuator's push towards its command (0 or force_n): time
    // constant tau, exact for a command held over a step. s, >= 0 (0 = instant).
    double actuator_lag_s = 0;
    // Transport delay of the on/off command: the push acts on the command of d seconds ago
    // (OFF before the run starts). Continuous in d: a fractional step delays the switch by
    // the matching share of the step's force. s, 0..0.2.
    double actuator_delay_s = 0;
    // Deadband of each actuator in force: Coulomb friction of the piston seals, up to F
    // along the actuator line against its extension rate, so the piston moves only while
    // the other forces along it exceed F (a net force inside +-F holds it still). Implicit:
    // a bounded constraint row per actuator and step. N, >= 0 (0 = off).
    double actuator_deadband_n = 0;
    // Saturating axial link springs: sigma = 1/x_s (1/m); the axial spring force becomes
    // F = k x / sqrt(1 + (sigma x)^2) (x the axial extension, either sign): stiffness
    // k / (1 + (sigma x)^2)^(3/2), always positive, force saturating at k x_s. Set each
    // step through the links' ERP from the extension at the start of the step (the
    // damping stays c). 1/m, >= 0.
    double spring_softening = 0;
    // The model's resolution: compliance 1/E of the lumps' own material (1/MPa). Above 0
    // each lump is built as two half-lumps (half the length and mass) joined at its centre
    // by a link of the silicone block between their centres, axial E A / l and bending
    // E I / l (A, I of the lump's y-z section, l half its length), damped at the links'
    // ratios of critical: twelve deformable bodies instead of six rigid ones. A lump
    // stiffer than the timestep resolves (h omega > 2.5 for its inner link) stays rigid.
    // 1/MPa, >= 0 (0 = rigid lumps, the paper's model).
    double lump_compliance_per_mpa = 0;
  } effects;

  // Actuator length at the rest pose: spacing + front_attach_x - rear_attach_x.
  double RestActuatorLength() const {
    return lumps.spacing_m + actuators.front_attach_x_m - actuators.rear_attach_x_m;
  }
  // Link (i, i+1), i = 1..5: flexure for odd i, segment for even i.
  const LinkStiffness& Link(int i) const { return i % 2 == 1 ? links.flexure : links.segment; }
};

// The model from a descriptor whose model is "caterpillar": every parameter of the descriptor
// must be a field of the model and every field must be in the descriptor.
absl::StatusOr<CaterpillarParams> CaterpillarParamsFrom(const robots::RobotDescriptor& d);
// A descriptor file's text (YAML or JSON), checked as robots::ParseDescriptor does: errors
// name source:line:column, the field, its unit and range:
//   "copy.yaml:13:20: lumps.mass_kg = -1 kg is outside [0.001, 1] kg".
absl::StatusOr<CaterpillarParams> ParseCaterpillarParams(const std::string& text,
                                                         const std::string& source);
absl::StatusOr<CaterpillarParams> LoadCaterpillarParams(const std::string& path);

// The built-in caterpillar (robots/caterpillar/robot.yaml, embedded at build time).
const robots::RobotDescriptor& CaterpillarDescriptor();
// Its model, built once. Throws std::runtime_error if the built-in is broken.
const CaterpillarParams& DefaultCaterpillarParams();

// The field of `p` that the descriptor parameter `name` sets (ground.friction_coefficient is
// infinite for the no-slip ground); NotFound when the model has no such field.
absl::StatusOr<double> GetField(const CaterpillarParams& p, std::string_view name);
absl::Status SetField(CaterpillarParams& p, std::string_view name, double value);

}  // namespace gaitforge::caterpillar
