#include "workers/effects/effects.h"

#include <cmath>
#include <stdexcept>

#include <algorithm>
#include <set>

namespace gaitforge::effects {

const std::vector<EffectInfo>& EffectCatalog() {
  static const std::vector<EffectInfo> catalog = {
      {"tether.constant",
       "Tether, constant pull",
       "Something trailing behind the robot (supply hoses, a cable, a tether) pulls its first "
       "body, by convention its rear, backwards (-x) with a constant force F at its centre. "
       "Paper 000 blames its pneumatic hoses for the hardware covering 35% of the simulated "
       "distance (11% to 74%).",
       {{"effect.tether_force_n", 0, 2.5, 0, "N"}},
       "Real travel per cycle shorter than simulated for every gait by a deficit that stays "
       "the same throughout a run; the rear of the robot falls behind most, backward slips "
       "show while it hops or slides; stroke amplitudes and timing still match.",
       "Run the same gait towards the tether's anchor and away from it, or with the tether "
       "supported overhead (paper 000's qualitative test): a tether's deficit flips or "
       "vanishes with its direction, a slope flips with the track's direction, friction and "
       "actuator effects do neither. A force gauge on the tether of the resting robot "
       "measures F.",
       "tether_body"},
      {"tether.growing",
       "Tether, growing with travel",
       "A tether drawn out as the robot moves away from its anchor (hoses, a cable): a "
       "backward pull on the first body growing with its forward travel from the start, "
       "F = k max(0, x - x0).",
       {{"effect.tether_stiffness_n_per_m", 0, 50, 0, "N/m"}},
       "Distance per cycle that decays along a run: the first cycles close to the "
       "simulation, later ones shorter; a longer run has a lower mean speed. (A constant "
       "tether gives the same deficit in every cycle.)",
       "Compare the first and last cycles of a long run, or start the same gait at "
       "different distances from the tether's anchor: a growing tether slows the robot with "
       "the distance travelled, a constant one does not.",
       "tether_body"},
      {"ground.slope",
       "Ground slope",
       "The test track is not level: gravity tilted about y by the slope s, "
       "(-g sin s, 0, -g cos s) in the ground frame; positive s is uphill along +x.",
       {{"effect.slope_rad", -0.3, 0.3, 0, "rad"}},
       "A travel deficit (uphill) or surplus (downhill) that follows the track's direction, "
       "largest for gaits with much airborne time or sliding; with finite friction the "
       "resting robot creeps downhill.",
       "Run the gait both ways along the same track: a slope changes sign with the heading "
       "(a tether follows its anchor instead); or measure the track with an inclinometer.",
       "ground"},
      {"friction.viscous",
       "Viscous drag",
       "A velocity-proportional resistance on every lump (air, adhesion and hysteresis of "
       "the soft feet), F = -c v in x and z, at the lump centre (paper 002 models resistive "
       "forces as viscous plus Coulomb friction). Explicit: stable while c h / m < 2.",
       {{"effect.drag_n_s_per_m", 0, 3, 0, "N s/m"}},
       "A deficit growing with speed: fast gaits and short periods lose more than slow ones; "
       "lower, shorter hops (smaller z amplitude), motion after each switch dying out sooner.",
       "A period sweep of one gait: drag costs travel roughly in proportion to speed, a "
       "tether a constant amount per cycle; or drag the passive robot at two speeds with a "
       "force gauge.",
       "every_body"},
      {"friction.anisotropic",
       "Finite, direction-dependent friction",
       "Finite Coulomb friction of the feet with one coefficient for sliding forward and "
       "another for sliding backward (texture of the soft feet, a ratchet-like contact), "
       "chosen per lump by the sign of its x velocity. 0 keeps the model's own ground in that "
       "direction (no slip where the ground has none), so the range is not continuous at 0; a "
       "robot with finite friction is as it is at its own coefficient, where fits start.",
       {{"effect.friction_forward", 0, 3, 0, ""}, {"effect.friction_backward", 0, 3, 0, ""}},
       "Feet that slip: markers of lumps that should stand still drift during their "
       "neighbours' strokes. Easy backward slip loses travel (the evolved forward gait even "
       "reverses); easy forward slip changes how much of each stroke becomes travel.",
       "Inclined-plane test (paper 001): tilt the passive robot until it slides, facing "
       "uphill and facing downhill; tan of each critical angle is the backward and the "
       "forward coefficient. A pull test with a force gauge in each direction does the same.",
       "ground"},
      {"actuator.lag",
       "Actuator lag",
       "Each actuator follows its command through a first-order lag with time constant tau: "
       "a pneumatic piston's push builds and releases pressure gradually (a dedicated "
       "model's effect.actuator_lag_s); on the generic builder a servo's commanded angle passes this "
       "lag before the servo's own (paper 001: servo lag; a slower or loaded servo, a "
       "filtering controller).",
       {{"effect.actuator_lag_s", 0, 0.1, 0, "s"}},
       "Strokes slower and smaller than simulated, most for short ON windows, short periods "
       "and fast joint sweeps; rise and fall both rounded, the joint angles late by a share "
       "of the cycle that grows with frequency; less work per cycle.",
       "Step response of one actuator on the bench, length, pressure or joint angle after a "
       "command step: a lag rounds the rise, a pure delay shifts it unchanged. A period "
       "sweep: a lag hurts short periods far more than long ones.",
       "actuators"},
      {"actuator.delay",
       "Actuator command delay",
       "Transport delay of the on/off command (valves, hose volume): each piston acts on "
       "its command of d seconds ago; continuous in d (a fraction of a step delays that "
       "share of the step's force).",
       {{"effect.actuator_delay_s", 0, 0.2, 0, "s"}},
       "The real motion is the simulated one later by a fixed time: the shape error's best "
       "shift is the same number of seconds in every recording (a larger share of the cycle "
       "at short periods) while stroke amplitudes match.",
       "Record the valve command together with an actuator's markers: a delay is a constant "
       "time between command and start of motion with an unchanged rise. A recording that "
       "starts at the first command tells it from a clock offset (nuisance.time_offset_s): "
       "only the delay keeps the robot still for d after the start.",
       "actuators"},
      {"actuator.force_scale",
       "Actuator force",
       "The piston force differs from the paper's 8.8 N (supply pressure, leaks, piston "
       "friction); all six actuators together.",
       {{"actuators.force_n", 3, 12, 8.8, "N"}},
       "Strokes faster or slower to their stops for every actuator alike, hops higher or "
       "lower, more or less airborne time; timing of the switches unchanged.",
       "Blocked force of one actuator with a load cell at the supply pressure, or the time "
       "to full stroke of a free actuator: a lag changes the shape of the rise, the force "
       "its rate."},
      {"actuator.deadband",
       "Actuator deadband",
       "Piston seal friction: each actuator moves only while the other forces along it "
       "(push, return spring, the body) exceed a band of +-F; inside it the piston holds "
       "(paper 001: servo deadband; for on/off pistons, stiction of the seals). Coulomb "
       "friction along the actuator line, implicit. A switched-off actuator returns only until "
       "the restoring force of its return spring and the links falls to F (on a free pair of "
       "lumps 1.9 mm short of rest at 1 N).",
       {{"effect.actuator_deadband_n", 0, 3, 0, "N"}},
       "Strokes that start late and stop short of the stops, lengths that stay put after a "
       "switch (a plateau before the return), the return incomplete; "
       "less travel for every gait, most for short ON windows.",
       "Pull one idle actuator apart with a force gauge: the force at which it starts to "
       "move is F (a lag or a weak push needs no force to move it); or switch it off at full "
       "stroke and watch whether it returns all the way.",
       "pistons"},
      {"servo.deadband",
       "Servo deadband",
       "A hobby servo's controller ignores position errors inside a band of +-b (the pulse "
       "width it does not resolve, gear backlash); inside the band it does not drive and its "
       "geared motor holds the joint (speed 0 up to its torque limit). Paper 001 blames "
       "servo deadband for part of its reality gap.",
       {{"effect.servo_deadband_rad", 0, 0.2, 0, "rad"}},
       "Joint angles that stop short of the commanded ones by up to b and stay put while "
       "the command turns (flat tops and bottoms of every sweep, a stroke smaller by about "
       "2b); small strokes lose most, relative to their size.",
       "Command slow steps of a fraction of a degree to one free servo and read its angle "
       "(a potentiometer, a camera): it moves only once the command is b away; a lag moves "
       "at once but slowly.",
       "servos"},
      {"contact.softness",
       "Soft ground contact",
       "The silicone feet (and the ground) compress: ODE's contact CFM (m/(N s)); the "
       "contact stiffness is ERP / (h CFM). The range spans decades: search its logarithm.",
       {{"ground.contact_cfm", 1e-6, 1e-2, 1e-5, "m/(N s)"}},
       "Lumps sitting lower than simulated (z offsets of the markers at rest), softer "
       "landings after hops, small extra compliance in every stroke.",
       "Static indentation of a foot under a known load; or the markers' z at rest against "
       "the geometry."},
      {"mass.offset",
       "Mass",
       "The lump masses differ from the CAD volume fill (tubing, fittings, glue): every lump "
       "scaled by the same factor; damping follows as a ratio of critical.",
       {{"scale.mass", 0.5, 2, 1, ""}},
       "Slower or faster dynamics for every gait: lower or higher hops, strokes reaching "
       "their stops later or sooner, a different best period of a period sweep.",
       "Weigh the robot with and without its hoses."},
      {"stiffness.scale",
       "Link stiffness",
       "The silicone's modulus (paper: 435 kPa) or the FEA stiffnesses off: all four link "
       "stiffnesses (axial and bending, flexure and segment) scaled by one factor.",
       {{"scale.link_stiffness", 0.3, 3, 1, ""}},
       "Neighbouring lumps follow a stroke more or less than simulated: body bending and "
       "stretching amplitudes off in proportion for small and large motions alike.",
       "Static deflection under known loads (paper 001): stretch and bend of a segment "
       "against the load; a straight line whose slope is off points here, a curved one at "
       "spring.softening."},
      {"spring.softening",
       "Softening axial springs",
       "The axial links soften as they stretch or compress (hyperelastic silicone, "
       "buckling flexures; paper 004: stiffness falling with deformation): axial force "
       "k x / sqrt(1 + (sigma x)^2) with sigma = 1/x_s, tangent stiffness "
       "k / (1 + (sigma x)^2)^(3/2), the force saturating at k x_s.",
       {{"effect.spring_softening", 0, 500, 0, "1/m"}},
       "Small motions match but large strokes stretch the links more than linear springs "
       "predict: the error grows with stroke amplitude and force, unlike a uniform "
       "stiffness scale.",
       "Load-extension curve of one flexure to several millimetres: linear springs give a "
       "straight line, softening bends it (sigma from its curvature).",
       "spring_links"},
      {"model.resolution",
       "Model resolution (deformable lumps)",
       "Rigid lumps stand for a continuum body (paper 000's second suspect: its \"highly "
       "approximate\" lumped model); a finer build of the same robot can disagree with the "
       "lumped one by centimetres per cycle, sometimes in sign. The next finer model: each "
       "lump a body its spring links join, split into two half-lumps joined at its centre by "
       "the material block between them (axial E A / l, bending E I / l, damped like the "
       "links); the parameter is the blocks' compliance 1/E. 0 is the rigid lumped model; a "
       "silicone of 435 kPa is 2.3 /MPa. Blocks stiffer than the timestep resolves stay rigid "
       "(at 1 ms: below about 1.4 /MPa), so the range is not continuous there.",
       {{"effect.lump_compliance_per_mpa", 0, 25, 0, "1/MPa"}},
       "Residuals that differ in sign between gaits and that no external force explains: "
       "strokes that move the lump centres less than simulated, lower hops, the shape of the "
       "body's bending wave off; largest for gaits that bend the body most or hop.",
       "Film one lump during a stroke (its front and rear faces separately), or compare with "
       "a finer lumped or FEA model on the same gaits: deformable lumps show as faces of one "
       "lump moving apart, an external force does not deform a lump.",
       "spring_links"},
      {"damping.scale",
       "Link damping",
       "The body dissipates more or less than the paper's critical damping: the silicone's "
       "viscoelastic loss and the pistons' internal friction (paper 004 identifies damping "
       "apart from stiffness and finds it growing with the bend; one factor is its first "
       "term). Both damping ratios (axial and bending, every link) scaled by one factor; the "
       "stiffnesses stay as they are.",
       {{"scale.link_damping", 0.1, 5, 1, ""}},
       "The transients of each stroke: with less damping the links overshoot and ring after "
       "every valve switch, with more the neighbouring lumps follow a stroke late and the "
       "strokes grow sluggish as the gait gets faster; hops change as the body keeps or "
       "loses the stroke's energy. The static shape is unchanged.",
       "Pluck one segment of the resting robot and film its decay (the logarithmic "
       "decrement, as paper 001 measured its knees): damping sets the decay, "
       "stiffness the frequency; or run one gait at two periods: a damping error grows "
       "with the stroke rate, a stiffness error does not."},
      {"joint.softening",
       "Bending joints softening with bend",
       "A continuum arm's backbone yields as it bends (paper 004: the fitted stiffness falls "
       "with |psi|, near yield): each bending joint's spring torque per axis "
       "k psi / sqrt(1 + (s psi)^2), psi the axis's deflection, tangent stiffness "
       "k / (1 + (s psi)^2)^(3/2): linear for small bends, saturating at k / s.",
       {{"effect.joint_softening_per_rad", 0, 10, 0, "1/rad"}},
       "Small motions match but large bends go further than simulated, and oscillate "
       "slower there: the error grows with the bend, not with the speed, and the fitted "
       "constant stiffness falls when recordings of larger bends are added.",
       "Static tip deflection under a few known loads or rod forces: constant springs give "
       "a straight load-deflection line, softening bends it (s from its curvature).",
       "bending_joints"},
      {"joint.damping_growth",
       "Bending joints damping more when bent",
       "Friction between the rods and the disks grows with the bend (paper 004: the fitted "
       "damping rises with |psi|): each bending joint's damping per axis c (1 + b psi^2).",
       {{"effect.joint_damping_growth_per_rad2", 0, 100, 0, "1/rad^2"}},
       "Motions about a straight arm decay as simulated, motions about a bent one decay "
       "faster: the error grows with the bend in the transients, not in the static shape.",
       "Pluck the tip at rest straight and held bent by constant rod forces, and compare the "
       "decays: the logarithmic decrement grows with the bend.",
       "bending_joints"},
      {"joint.stiffening",
       "Bending joints stiffening with speed",
       "Dynamic stiffening of the backbone (paper 004: the fitted stiffness rises with the "
       "speed of the motion): each bending joint's spring torque per axis times "
       "(1 + g |w|), w the axis's bending rate.",
       {{"effect.joint_stiffening_s_per_rad", 0, 5, 0, "s/rad"}},
       "Slow motions and the static shape match, fast ones bend less and ring faster than "
       "simulated: the error grows with the drive's frequency, not with the bend.",
       "Drive the rods with one amplitude at several frequencies: a stiffening arm's "
       "amplitude falls and its phase lag shrinks faster with frequency than the constant "
       "model's.",
       "bending_joints"},
      {"contact.creep",
       "Creeping contact",
       "Feet that creep under a sideways load instead of sticking: the sliding speed of a "
       "touching foot grows in proportion to the friction force it carries, v = s F, up to "
       "the Coulomb limit (ODE's force-dependent slip). Soft silicone feet shear and "
       "regularised contact laws (MuJoCo's soft constraints, penalty contacts) do this; the "
       "model's ground sticks. The range spans decades; its lower edge is the model's own "
       "sticking ground (no slip), so the range is not continuous there.",
       {{"effect.contact_slip_m_per_n_s", 1e-5, 1, 1e-5, "m/(N s)"}},
       "Feet that should stand still drift slowly backwards during every stroke that pushes "
       "against them, more under larger pushes and longer strokes; less travel for every "
       "gait, the loss growing with the stroke's force and duration rather than with the "
       "distance travelled; a resting robot on a slight slope creeps downhill.",
       "Push a resting robot sideways with a force gauge below the force that makes it "
       "slide and film a foot: a creeping contact moves at a speed proportional to the "
       "force, a Coulomb contact holds until it breaks away.",
       "ground"},
  };
  return catalog;
}

bool IsStructural(std::string_view id) {
  static const std::set<std::string_view> structural = {
      "friction.anisotropic", "contact.softness", "model.resolution",
      "damping.scale",        "stiffness.scale",  "mass.offset",
      "contact.creep"};
  return structural.count(id) > 0;
}

const EffectInfo* FindEffect(std::string_view id) {
  for (const EffectInfo& e : EffectCatalog()) {
    if (e.id == id) return &e;
  }
  return nullptr;
}

std::vector<EffectInfo> EffectsFor(const robots::RobotDescriptor& d) {
  std::vector<EffectInfo> all = EffectCatalog();
  for (const robots::Suspect& s : d.suspects) {
    EffectInfo e{s.id, s.name, s.meaning, {}, s.where, s.experiment};
    for (const auto& f : s.fit) e.params.push_back({f.name, f.lo, f.hi, f.nominal, f.unit});
    all.push_back(std::move(e));
  }
  return all;
}

namespace {

// The robot's own ground friction coefficient, when it is finite and positive (0 otherwise:
// none, no slip, or a parameter the descriptor lacks).
double GroundFriction(const robots::RobotDescriptor& d) {
  if (!d.ground) return 0;
  try {
    const double mu = d.ground->friction.Eval([&](const std::string& n) { return d.Value(n); });
    return std::isfinite(mu) && mu > 0 ? mu : 0;
  } catch (const std::out_of_range&) {
    return 0;
  }
}

}  // namespace

std::optional<EffectInfo> FindEffect(std::string_view id, const robots::RobotDescriptor& d) {
  if (const EffectInfo* e = FindEffect(id)) {
    EffectInfo out = *e;
    // Direction-dependent friction leaves a finite-friction robot as it is at its own
    // coefficient in both directions, not at 0 (which stands for it but is no point of a
    // continuous range): a fit starts there and the range rule reads "no effect" there.
    if (const double mu = GroundFriction(d); id == "friction.anisotropic" && mu > 0)
      for (auto& p : out.params)
        if (mu >= p.lo && mu <= p.hi) p.nominal = mu;
    return out;
  }
  for (EffectInfo& e : EffectsFor(d))
    if (e.id == id) return std::move(e);
  return std::nullopt;
}

bool HasPart(const robots::RobotDescriptor& d, std::string_view part) {
  if (d.model != "generic") return false;
  if (part == "tether_body" || part == "every_body") return !d.bodies.empty();
  if (part == "ground") return d.ground.has_value();
  // A lag or delay of the command: the builder applies it to servos and pistons.
  if (part == "actuators")
    return std::any_of(d.actuators.begin(), d.actuators.end(), [](const robots::Actuator& a) {
      return a.type == "servo" || a.type == "piston";
    });
  if (part == "bending_joints")
    return std::any_of(d.joints.begin(), d.joints.end(), [](const robots::Joint& j) {
      return j.type == "universal" && (j.stiffness || j.damping);
    });
  if (part == "spring_links")
    return std::any_of(d.joints.begin(), d.joints.end(),
                       [](const robots::Joint& j) { return j.type == "spring_link"; });
  if (part == "servos" || part == "pistons") {
    const std::string type = part == "servos" ? "servo" : "piston";
    return std::any_of(d.actuators.begin(), d.actuators.end(),
                       [&type](const robots::Actuator& a) { return a.type == type; });
  }
  return false;
}

std::string WhyNotApplicable(const EffectInfo& e, const robots::RobotDescriptor& d) {
  if (e.params.empty()) return "it has no parameter to fit";
  for (const robots::RuledOut& r : d.ruled_out)
    if (r.id == e.id) return d.name + "'s descriptor rules it out (" + r.mark.ToString() + "): " + r.why;
  const std::vector<std::string> own = d.CalibratableNames();
  for (const auto& p : e.params) {
    if (std::find(own.begin(), own.end(), p.name) != own.end()) continue;
    if (!e.attaches.empty() && HasPart(d, e.attaches)) continue;
    if (!e.attaches.empty())
      return d.model == "generic"
                 ? "it attaches to " + e.attaches + ", which " + d.name + " lacks"
                 : "it attaches to " + e.attaches + " through the generic builder, and " +
                       d.name + "'s model (" + d.model + ") has no " + p.name;
    return d.name + " has no calibratable " + p.name;
  }
  return "";
}

std::vector<std::string> FittableNames(const robots::RobotDescriptor& d) {
  std::vector<std::string> names = d.CalibratableNames();
  for (const EffectInfo& e : EffectCatalog()) {
    if (e.attaches.empty() || !HasPart(d, e.attaches)) continue;
    for (const auto& p : e.params)
      if (std::find(names.begin(), names.end(), p.name) == names.end()) names.push_back(p.name);
  }
  return names;
}

const EffectInfo::Param* BuilderParam(std::string_view name, const robots::RobotDescriptor& d) {
  for (const EffectInfo& e : EffectCatalog()) {
    if (e.attaches.empty() || !HasPart(d, e.attaches)) continue;
    for (const auto& p : e.params)
      if (p.name == name) return &p;
  }
  return nullptr;
}

}  // namespace gaitforge::effects
