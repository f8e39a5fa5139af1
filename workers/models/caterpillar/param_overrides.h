#pragma once
// Calibratable parameters of the caterpillar model by name: what a calibration study's
// genes mean ("caterpillar.calibration", calibration_objective.h). Each name sets one
// field of CaterpillarParams (absolute) or multiplies a group of fields (scale.*); after
// every change the touched fields are checked against the ranges of caterpillar.yaml.
//
// Absolute (the value replaces the field; units and ranges as in caterpillar.yaml):
//   actuators.force_n                          N        [0, 100]
//   actuators.return_spring_n_per_m            N/m      [0, 1e4]
//   actuators.max_length_m                     m        [0.001, 1], above min_length_m and
//                                                        at least the rest actuator length
//   links.flexure.axial_stiffness_n_per_m      N/m      [1, 1e6]
//   links.flexure.bending_stiffness_nm_per_rad N m/rad  [1e-4, 100]
//   links.segment.axial_stiffness_n_per_m      N/m      [1, 1e6]
//   links.segment.bending_stiffness_nm_per_rad N m/rad  [1e-4, 100]
//   links.axial_damping_ratio                  of critical [0.01, 10]
//   links.bending_damping_ratio                of critical [0.01, 10]
//   lumps.mass_kg                              kg       [0.001, 1]
//   ground.contact_erp                         -        [0.01, 1]
//   ground.contact_cfm                         m/(N s)  [0, 1e-2]
//   ground.friction_coefficient                -        [0, 10]; also sets finite
//                                                        (Coulomb) friction
// Candidate effects (CaterpillarParams::Effects, caterpillar_params.h; not in
// caterpillar.yaml, 0 = off; their catalog: workers/effects/effects.h):
//   effect.tether_force_n                      N        [0, 20]   constant backward pull on lump 1
//   effect.tether_stiffness_n_per_m            N/m      [0, 1000] + k * forward travel of lump 1
//   effect.slope_rad                           rad      [-0.3, 0.3] ground slope, + uphill along +x
//   effect.drag_n_s_per_m                      N s/m    [0, 10]   viscous drag on every lump
//                                                        (explicit: stable while c h / m < 2)
//   effect.friction_forward                    -        [0, 10]   Coulomb coefficient sliding +x
//   effect.friction_backward                   -        [0, 10]   ... sliding -x (0: model's own)
//   effect.actuator_lag_s                      s        [0, 1]    first-order lag of the push
//   effect.actuator_delay_s                    s        [0, 0.2]  transport delay of on/off
//   effect.actuator_deadband_n                 N        [0, 20]   piston seal friction: no
//                                                        motion while |net force| < F
//   effect.spring_softening                    1/m      [0, 1000] 1/x_s: axial spring force
//                                                        k x / sqrt(1 + (x/x_s)^2)
// Scale (a positive finite factor multiplying the current value; the result must stay in
// the fields' ranges):
//   scale.link_stiffness     all four link stiffnesses (axial and bending, flexure and segment)
//   scale.axial_stiffness    the two axial stiffnesses
//   scale.bending_stiffness  the two bending stiffnesses
//   scale.mass               lumps.mass_kg (damping is a ratio of critical, so it follows)
//   scale.link_damping       both damping ratios (axial and bending, every link and the
//                            half-lump blocks of effect.lump_compliance_per_mpa)
// Names are applied in order; a scale multiplies whatever the field holds at that point.
//
// Nuisance names are parameters of the comparison, not of the model; the objective handles
// them and SetParam rejects them:
//   nuisance.time_offset_s   s   recording time t corresponds to simulated time t + offset
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"
#include "workers/models/caterpillar/caterpillar_params.h"

namespace gaitforge::caterpillar {

inline constexpr char kTimeOffsetParam[] = "nuisance.time_offset_s";

// The model names SetParam accepts, in the order documented above.
const std::vector<std::string>& CalibratableParamNames();
// The nuisance names (handled by the calibration objective).
const std::vector<std::string>& NuisanceParamNames();
bool IsNuisanceParam(std::string_view name);

// Sets `name` to `value` (or multiplies, for scale.*). On error `params` is unchanged and
// the message names the parameter, the value and the allowed range; an unknown name lists
// the known ones.
absl::Status SetParam(CaterpillarParams& params, std::string_view name, double value);

// Checks the fields SetParam may change against the ranges of caterpillar.yaml and the
// actuator length relations (min < max, rest length within [min, max]).
absl::Status ValidateCalibratableFields(const CaterpillarParams& params);

}  // namespace gaitforge::caterpillar
