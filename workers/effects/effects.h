#pragma once
// The catalog of candidate physical effects that the gap finder may attach to a robot's
// model (issue 8): the "missing physics" the papers name (../shared/papers/README.md) as
// compact parametric forms with a physical meaning. Each effect is expressed by calibratable
// parameters by name, so that a calibration study can fit them: parameters a robot's
// descriptor declares itself (with its own allowed range), or parameters the
// generic builder adds to any robot with the part the effect attaches to.
//
// Pure data: this library does not depend on a model or on ODE (only on robots/).
//
// Where an effect applies: its parameters are either a robot's own (a calibratable
// parameter or scale of its descriptor: actuators.force_n, scale.mass; an effect.* parameter
// it declares) or, for an effect that declares the part it `attaches` to, parameters
// the generic builder (workers/models/generic/) adds to any robot with that part.
//
// Ids are stable (a study or report may store them):
//   tether.constant tether.growing ground.slope friction.viscous friction.anisotropic
//   actuator.lag actuator.delay actuator.force_scale actuator.deadband servo.deadband
//   contact.softness mass.offset
//   stiffness.scale spring.softening model.resolution damping.scale
//   joint.softening joint.damping_growth joint.stiffening
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "robots/descriptor.h"

namespace gaitforge::effects {

struct EffectInfo {
  std::string id;       // stable, e.g. "tether.constant"
  std::string name;     // short human name
  std::string meaning;  // the physics and its parametric form
  struct Param {
    std::string name;   // a name generic::ParamValues::Set accepts
    // The range a fit may search, and the value that leaves the model as it is (the effect
    // absent: 0 for effect.*, 1 for scale.*, the descriptor's value for an absolute
    // field). A range wide enough for the paper's story (tether: the hardware travelled
    // about 35% of the simulated distance).
    double lo, hi, nominal;
    std::string unit;
  };
  std::vector<Param> params;  // empty: not available as a fitted effect
  std::string where;          // the residual pattern it explains, in words
  std::string experiment;     // an experiment that tells it apart from similar effects
  // The part the generic builder attaches it to (kParts); empty: not a builder effect.
  std::string attaches = {};
};

// The parts an effect may attach to, and what each means on a generic robot:
//   tether_body  the descriptor's first body (by convention its rear), pulled at its centre
//   every_body   every body, at its centre
//   ground       the ground contacts
//   actuators    every actuator's command
//   servos       every position servo's controller
//   pistons      every piston (its line between two bodies)
//   spring_links every spring link of a planar robot
//   bending_joints every universal joint with a spring or damper (paper 004's arm; hinge
//                joints do not take these effects yet)
inline const std::vector<std::string> kParts = {"tether_body", "every_body", "ground",
                                                "actuators",   "servos",     "pistons",
                                                "spring_links", "bending_joints"};

// Every effect, in the order of the ids above.
const std::vector<EffectInfo>& EffectCatalog();
// The effect with this id, or nullptr.
const EffectInfo* FindEffect(std::string_view id);

// The effects a diagnosis of robot d may try: the catalog's, then the robot's own suspects
// (its descriptor's `suspects:`, as entries without a part).
std::vector<EffectInfo> EffectsFor(const robots::RobotDescriptor& d);
// The catalog's effect with this id, else robot d's suspect with it; nullopt when neither.
std::optional<EffectInfo> FindEffect(std::string_view id, const robots::RobotDescriptor& d);

// Whether robot d has the part (kParts) and a model that attaches effects to it (generic).
bool HasPart(const robots::RobotDescriptor& d, std::string_view part);

// True for the effects that say what a model gets wrong everywhere rather than what it
// left out: its contact and friction law, resolution, damping, stiffness, mass. The gap
// finder's structure-first stage (docs/diagnosis.md) fits them before any other effect.
bool IsStructural(std::string_view id);

// "" when every parameter of `e` is one robot d's model takes: a calibratable name of its
// descriptor, or a builder effect's parameter on a part d has; otherwise why not, in words
// (also when d's descriptor rules the effect out: its `ruled_out`, with the reason).
std::string WhyNotApplicable(const EffectInfo& e, const robots::RobotDescriptor& d);

// What a calibration of robot d may fit: its calibratable names (parameters, then scales),
// then the parameters of builder effects on parts it has.
std::vector<std::string> FittableNames(const robots::RobotDescriptor& d);

// The builder-effect parameter `name` (effect.*) when some effect attaching to a part that
// robot d has takes it; nullptr otherwise.
const EffectInfo::Param* BuilderParam(std::string_view name, const robots::RobotDescriptor& d);

}  // namespace gaitforge::effects
