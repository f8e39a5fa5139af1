#pragma once
// The catalog of candidate physical effects that the gap finder may attach to the caterpillar
// model (issue 8): the "missing physics" the papers name (../shared/papers/README.md) as
// compact parametric forms with a physical meaning. Each effect is expressed by calibratable
// parameters by name (workers/models/caterpillar/param_overrides.h), so that the calibration
// machinery ("caterpillar.calibration") can fit them; the model side of the effect.* names
// is CaterpillarParams::Effects (caterpillar_params.h) applied in CaterpillarSim.
//
// Pure data: this library does not depend on the model or on ODE.
//
// Ids are stable (a study or report may store them):
//   tether.constant tether.growing ground.slope friction.viscous friction.anisotropic
//   actuator.lag actuator.delay actuator.force_scale actuator.deadband contact.softness mass.offset
//   stiffness.scale spring.softening model.resolution damping.scale
#include <string>
#include <string_view>
#include <vector>

namespace gaitforge::effects {

struct EffectInfo {
  std::string id;       // stable, e.g. "tether.constant"
  std::string name;     // short human name
  std::string meaning;  // the physics and its parametric form
  struct Param {
    std::string name;   // a SetParam name (param_overrides.h)
    // The range a fit may search, and the value that leaves the model as it is (the effect
    // absent: 0 for effect.*, 1 for scale.*, the caterpillar.yaml value for an absolute
    // field). A range wide enough for the paper's story (tether: the hardware travelled
    // about 35% of the simulated distance).
    double lo, hi, nominal;
    std::string unit;
  };
  std::vector<Param> params;  // empty: not available as a fitted effect
  std::string where;          // the residual pattern it explains, in words
  std::string experiment;     // an experiment that tells it apart from similar effects
};

// Every effect, in the order of the ids above.
const std::vector<EffectInfo>& EffectCatalog();
// The effect with this id, or nullptr.
const EffectInfo* FindEffect(std::string_view id);

}  // namespace gaitforge::effects
