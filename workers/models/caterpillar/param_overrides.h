#pragma once
// Calibratable parameters of the caterpillar model by name: what a calibration study's
// genes mean ("caterpillar.calibration", calibration_objective.h). The names, units and
// ranges are the descriptor's (robots/caterpillar/robot.yaml): every parameter marked
// `calibrate: true` (its value replaces the field; ground.friction_coefficient also makes
// the ground Coulomb) and every scale ("scale.link_stiffness": a positive finite factor
// multiplying the parameters it names, each of which must stay in its range). After every
// change the calibratable fields are checked against their ranges and the descriptor's
// relations (the stroke, the rest actuator length). docs/calibration.md lists them.
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

// Checks the fields SetParam may change against their descriptor ranges, and every relation
// of the descriptor (min < max stroke, rest length within it, ...).
absl::Status ValidateCalibratableFields(const CaterpillarParams& params);

}  // namespace gaitforge::caterpillar
