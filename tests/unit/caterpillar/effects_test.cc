// Candidate physical effects (CaterpillarParams::Effects, issue 8) and their catalog
// (workers/effects/effects.h): every effect at zero leaves the model bit-identical; each at a
// moderate value moves the robot the way its physics says; SetParam guards the ranges.
//
// Whole hopping gaits are chaotic in any numerical change (../shared/robots/caterpillar.md),
// so effects on travel are judged on the mean over five timesteps (0.8 .. 1.2 ms) of the
// distance per cycle over 10 measured cycles; mechanisms are checked exactly on gentle or
// passive motions.
#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "gmock/gmock.h"
#include "tests/unit/caterpillar/test_helpers.h"
#include "robots/registry.h"
#include "workers/effects/effects.h"
#include "workers/models/caterpillar/caterpillar_eval.h"
#include "workers/models/caterpillar/gait.h"
#include "workers/models/caterpillar/param_overrides.h"

namespace gaitforge::caterpillar::testing {
namespace {

using ::testing::HasSubstr;

// An evolved forward gait: about +3 cm per cycle over 10 cycles.
const std::vector<double> kForwardGenes = {
    0.066346016790415963, 0.92228296711382263, 0.99884798501519678, 0.91495911032617716,
    0.013764065590901597, 0.027395295966066602, 0.32783986902260742, 0.36116692841980558,
    0.1062628441354091,   0.40778045503790639, 0.36272688662110386, 0.30411357539492101,
    0.35444634996911673};

const std::vector<std::string> kEffectNames = {
    "effect.tether_force_n",   "effect.tether_stiffness_n_per_m", "effect.slope_rad",
    "effect.drag_n_s_per_m",   "effect.friction_forward",         "effect.friction_backward",
    "effect.actuator_lag_s",   "effect.actuator_delay_s",         "effect.spring_softening",
    "effect.actuator_deadband_n", "effect.lump_compliance_per_mpa"};

CaterpillarParams With(const std::string& name, double value) {
  CaterpillarParams p = Params();
  const absl::Status s = SetParam(p, name, value);
  EXPECT_TRUE(s.ok()) << s;
  return p;
}

GaitEvaluation Evaluate(const CaterpillarParams& p, double timestep_s = 0,
                        double marker_rate_hz = 0) {
  EvalOptions o;
  o.settle_cycles = 2;
  o.measured_cycles = 10;
  o.timestep_s = timestep_s;
  o.marker_rate_hz = marker_rate_hz;
  return EvaluateGait(p, *Gait::FromGenes(kForwardGenes), o);
}

// Distance per cycle (m) of the forward gait, mean over five timesteps.
double MeanTravel(const CaterpillarParams& p) {
  double sum = 0;
  for (double h : {0.8e-3, 0.9e-3, 1.0e-3, 1.1e-3, 1.2e-3}) {
    const GaitEvaluation e = Evaluate(p, h);
    EXPECT_TRUE(e.valid) << e.reason;
    sum += e.distance_per_cycle_m;
  }
  return sum / 5;
}

double FreeTravel() {
  static const double free = MeanTravel(Params());
  return free;
}

void ExpectSameEvaluation(const GaitEvaluation& a, const GaitEvaluation& b,
                          const std::string& what) {
  EXPECT_EQ(a.valid, b.valid) << what;
  EXPECT_EQ(a.distance_per_cycle_m, b.distance_per_cycle_m) << what;
  EXPECT_EQ(a.max_body_pitch_rad, b.max_body_pitch_rad) << what;
  EXPECT_EQ(a.max_stroke_m, b.max_stroke_m) << what;
  EXPECT_EQ(a.min_actuator_length_m, b.min_actuator_length_m) << what;
  EXPECT_EQ(a.max_actuator_length_m, b.max_actuator_length_m) << what;
  EXPECT_EQ(a.actuator_energy_j, b.actuator_energy_j) << what;
  EXPECT_EQ(a.airborne_fraction, b.airborne_fraction) << what;
  EXPECT_EQ(a.markers.t, b.markers.t) << what;
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(a.markers.x[k], b.markers.x[k]) << what << " m" << k + 1;
    EXPECT_EQ(a.markers.z[k], b.markers.z[k]) << what << " m" << k + 1;
  }
}

// ---------------------------------------------------------------------------------------
// Off at zero.

TEST(CaterpillarEffects, EveryEffectAtZeroLeavesTheModelBitIdentical) {
  const GaitEvaluation ref = Evaluate(Params(), 0, 100);
  ASSERT_TRUE(ref.valid) << ref.reason;
  // The model's numbers before the effects existed (same build options): a deliberate
  // change of the model may move them, the effects code may not.
  EXPECT_EQ(ref.distance_per_cycle_m, 0.031132671373804023);
  for (const std::string& name : kEffectNames) {
    ExpectSameEvaluation(Evaluate(With(name, 0.0), 0, 100), ref, name);
  }
  // The finite-friction path of the ground contacts is shared with friction.anisotropic.
  CaterpillarParams finite = Params();
  ASSERT_TRUE(SetParam(finite, "ground.friction_coefficient", 0.5).ok());
  const GaitEvaluation f = Evaluate(finite);
  EXPECT_EQ(f.distance_per_cycle_m, -0.0076538640996944365);
  ASSERT_TRUE(SetParam(finite, "effect.friction_forward", 0).ok());
  ASSERT_TRUE(SetParam(finite, "effect.friction_backward", 0).ok());
  EXPECT_EQ(Evaluate(finite).distance_per_cycle_m, f.distance_per_cycle_m);
}

// ---------------------------------------------------------------------------------------
// Each effect at a moderate value, in its physical direction.

TEST(CaterpillarEffects, TetherReducesForwardTravel) {
  const double free = FreeTravel();
  ASSERT_GT(free, 0.02) << "the evolved gait moves forward about 3 cm per cycle";
  EXPECT_LT(MeanTravel(With("effect.tether_force_n", 0.8)), 0.8 * free);
  EXPECT_LT(MeanTravel(With("effect.tether_stiffness_n_per_m", 10)), 0.6 * free);
}

// The paper's story: the hardware travelled about 35% of the simulated distance, blamed on
// the hoses. A constant pull of about 1.1 N (within the catalog's range) does that to this
// gait: mean over ten timesteps 0.8 .. 1.25 ms, 50% at 1.0 N, 41% at 1.05 N, 29% at 1.1 N,
// 18% at 1.2 N, reversed from about 1.5 N (a single run at 1 ms: 47% at 1.1 N). Here: the
// five-timestep mean (33%).
TEST(CaterpillarEffects, TetherOfAboutOneNewtonLeavesAThirdOfTheTravel) {
  constexpr double kTether = 1.1;
  const auto* tether = effects::FindEffect("tether.constant");
  ASSERT_NE(tether, nullptr);
  ASSERT_EQ(tether->params.size(), 1u);
  EXPECT_EQ(tether->params[0].name, "effect.tether_force_n");
  EXPECT_GT(tether->params[0].hi, kTether);
  const double ratio = MeanTravel(With("effect.tether_force_n", kTether)) / FreeTravel();
  EXPECT_GT(ratio, 0.2);
  EXPECT_LT(ratio, 0.5);
}

TEST(CaterpillarEffects, UphillSlopeReducesTravelAndDownhillDoesNot) {
  const double free = FreeTravel();
  const double uphill = MeanTravel(With("effect.slope_rad", 0.3));
  const double downhill = MeanTravel(With("effect.slope_rad", -0.2));
  EXPECT_LT(uphill, 0.85 * free);
  EXPECT_GT(downhill, free);
}

// The tilted gravity exactly: the passive robot on a slope steeper than its (finite,
// Coulomb) friction slides downhill at g (sin s - mu cos s); a gentler one holds.
TEST(CaterpillarEffects, PassiveRobotSlidesDownASteepSlopeAtTheCoulombRate) {
  const double g = Params().simulation.gravity_m_per_s2;
  for (double slope : {0.2, -0.2, 0.05}) {
    CaterpillarParams p = With("effect.slope_rad", slope);
    ASSERT_TRUE(SetParam(p, "effect.friction_forward", 0.1).ok());
    ASSERT_TRUE(SetParam(p, "effect.friction_backward", 0.1).ok());
    CaterpillarSim sim(p);
    const double x0 = MeanX(sim.body());
    Simulate(sim, 0.3, 0);
    const double t = sim.time();
    const double down = std::sin(std::fabs(slope)) - 0.1 * std::cos(slope);
    const double expected = down > 0 ? -std::copysign(0.5 * g * down * t * t, slope) : 0.0;
    EXPECT_NEAR(MeanX(sim.body()) - x0, expected, 0.01 * std::fabs(expected) + 1e-6)
        << "slope " << slope;
  }
}

TEST(CaterpillarEffects, DragReducesSpeed) {
  EXPECT_LT(MeanTravel(With("effect.drag_n_s_per_m", 1.0)), 0.7 * FreeTravel());
  // Mechanism: a free chain coasting at 0.1 m/s loses speed as v (1 - c h / m)^n.
  const double c = 0.5;
  const CaterpillarParams p = With("effect.drag_n_s_per_m", c);
  CaterpillarSim sim(p, FreeChain());
  for (int k = 0; k < sim.body().lump_count(); ++k) {
    dBodySetLinearVel(sim.body().lump(k), 0.1, 0, 0.05);
  }
  Simulate(sim, 0.1, 0);
  const double decay = std::pow(1 - c * sim.timestep() / p.lumps.mass_kg, sim.steps());
  for (int k = 0; k < sim.body().lump_count(); ++k) {
    EXPECT_NEAR(sim.body().Velocity(k).x, 0.1 * decay, 1e-9) << "lump " << k + 1;
    EXPECT_NEAR(sim.body().Velocity(k).z, 0.05 * decay, 1e-9) << "lump " << k + 1;
  }
}

// Low backward friction lets the feet slip back: the forward gait loses its travel (it
// even reverses: with no-slip forwards and slipping backwards every stroke pushes back).
// Direction is chosen per lump: on an uphill slope only the backward coefficient matters.
TEST(CaterpillarEffects, AnisotropicFrictionActsByDirectionOfSliding) {
  EXPECT_LT(MeanTravel(With("effect.friction_backward", 0.2)), 0);
  const double g = Params().simulation.gravity_m_per_s2;
  const double slope = 0.2;  // tan = 0.203
  auto slide = [&](double forward, double backward, double s) {
    CaterpillarParams p = With("effect.slope_rad", s);
    EXPECT_TRUE(SetParam(p, "effect.friction_forward", forward).ok());
    EXPECT_TRUE(SetParam(p, "effect.friction_backward", backward).ok());
    CaterpillarSim sim(p);
    const double x0 = MeanX(sim.body());
    Simulate(sim, 0.3, 0);
    return MeanX(sim.body()) - x0;
  };
  const double t = 0.3;
  const double expected = 0.5 * g * (std::sin(slope) - 0.15 * std::cos(slope)) * t * t;
  EXPECT_NEAR(slide(5, 0.15, slope), -expected, 0.01 * expected);  // slides back
  EXPECT_NEAR(slide(5, 0.3, slope), 0, 1e-6);                      // holds
  EXPECT_NEAR(slide(0.15, 5, -slope), expected, 0.01 * expected);  // downhill: forward
  EXPECT_NEAR(slide(0.3, 5, -slope), 0, 1e-6);
}

// A short pulse of T1 (lumps 1, 2): the lagged push builds up more slowly, so the stroke
// is smaller, the more the longer the lag.
TEST(CaterpillarEffects, ActuatorLagReducesStrokeAmplitude) {
  for (double pulse : {0.01, 0.02}) {
    double previous = 1;
    for (double lag : {0.0, 0.005, 0.02, 0.05}) {
      const CaterpillarParams p = With("effect.actuator_lag_s", lag);
      CaterpillarSim sim(p);
      double top = 0;
      for (int n = 0; n < 300; ++n) {
        ASSERT_TRUE(sim.Step(sim.time() < pulse - 1e-9 ? 1u : 0u).ok);
        top = std::max(top, sim.actuator_lengths()[0] - p.actuators.min_length_m);
      }
      EXPECT_LT(top, previous) << "pulse " << pulse << " lag " << lag;
      previous = top;
    }
  }
  // The evolved gait's strokes do less work.
  EXPECT_LT(Evaluate(With("effect.actuator_lag_s", 0.02)).actuator_energy_j,
            0.5 * Evaluate(Params()).actuator_energy_j);
}

// A delay of whole steps shifts the motion in time: the delayed run is exactly the
// undelayed gait started that many steps late (the robot rests, all OFF, until the first
// command arrives); a fractional delay lies in between.
TEST(CaterpillarEffects, ActuatorDelayShiftsTheMotionInTime) {
  const Gait gait = *Gait::FromGenes(kForwardGenes);
  constexpr int kSteps = 400;
  // delay_steps >= 0: the model without delay, commanded OFF for that many steps and then
  // the gait from its start; < 0: the model with effect.actuator_delay_s = delay_s.
  auto lengths = [&](double delay_s, int late_steps) {
    CaterpillarSim sim(With("effect.actuator_delay_s", late_steps >= 0 ? 0 : delay_s));
    std::vector<double> l;
    for (int n = 0; n < kSteps; ++n) {
      uint32_t mask = gait.OnMask(sim.time());
      if (late_steps >= 0) mask = n < late_steps ? 0 : gait.OnMask((n - late_steps) * sim.timestep());
      EXPECT_TRUE(sim.Step(mask).ok);
      l.push_back(sim.actuator_lengths()[0]);
    }
    return l;
  };
  auto first_rise = [](const std::vector<double>& l) {
    for (size_t n = 0; n < l.size(); ++n) {
      if (l[n] > l[0] + 0.002) return static_cast<int>(n);
    }
    return -1;
  };
  const std::vector<double> l0 = lengths(0, -1), l20 = lengths(0.020, -1);
  EXPECT_EQ(l20, lengths(0, 20));
  EXPECT_EQ(first_rise(l20), first_rise(l0) + 20);
  // Fractional: 20.5 steps rises between 20 and 21.
  const std::vector<double> l20h = lengths(0.0205, -1), l21 = lengths(0.021, -1);
  const int rise = first_rise(l20);
  EXPECT_LT(l20h[rise], l20[rise]);
  EXPECT_GT(l20h[rise], l21[rise]);
  // Over the evolved gait's steady cycles the travel per cycle is about unchanged.
  EXPECT_NEAR(MeanTravel(With("effect.actuator_delay_s", 0.02)), FreeTravel(),
              0.3 * FreeTravel());
}

// The deadband: lumps 1 and 2 with T1 and B1, no ground or gravity. T1 pushed for 0.3 s,
// then switched off. Pushing against a band F, it comes to rest no further out than the
// model without a band under a push of 8.8 - F (Coulomb: the band takes F off a push that
// moves the piston; it sticks as soon as the net force drops inside the band, so up to 0.5
// mm short of that, while the links still settle). Switched off, it returns to its rest length without a band, and with
// one stops where the restoring force (return spring and links) falls to F: further out
// the wider the band. A band above the 8.8 N push never lets it move.
TEST(CaterpillarEffects, ActuatorDeadbandHoldsThePistonInsideTheBand) {
  auto stroke_after = [&](double band, double force, double on_s, double off_s) {
    CaterpillarParams p = With("effect.actuator_deadband_n", band);
    p.actuators.force_n = force;
    BuildOptions o = FreeChain(1, 2);
    o.actuators = true;
    CaterpillarSim sim(p, o);
    Simulate(sim, on_s, 1u);  // T1 on, B1 off
    const double on = sim.actuator_lengths()[0] - p.actuators.min_length_m;
    Simulate(sim, off_s, 0u);
    return std::make_pair(on, sim.actuator_lengths()[0] - p.actuators.min_length_m);
  };
  const double push = Params().actuators.force_n;
  double previous_off = -1;
  for (double band : {0.0, 1.0, 2.0, 3.0}) {
    const auto [on, off] = stroke_after(band, push, 0.3, 0.5);
    if (band > 0) {
      const double reduced_push = stroke_after(0, push - band, 0.3, 0).first;
      EXPECT_LT(on, reduced_push + 5e-5) << "band " << band;
      EXPECT_GT(on, reduced_push - 6e-4) << "band " << band;
      EXPECT_GT(off, previous_off + 5e-4) << "band " << band;
    } else {
      EXPECT_NEAR(on, Params().actuators.max_length_m - Params().actuators.min_length_m, 2e-4);
      EXPECT_LT(off, 1e-5) << "no band: back to rest";
    }
    previous_off = off;
  }
  EXPECT_LT(stroke_after(10, push, 0.3, 0).first, 1e-4) << "band 10 N > 8.8 N push";
  // The band slows the stroke: less extension after 10 ms.
  EXPECT_LT(stroke_after(3, push, 0.01, 0).first, 0.8 * stroke_after(0, push, 0.01, 0).first);
  // On the ground, the evolved gait's travel changes: 1.4 against 2.9 cm per cycle at 1.5 N.
  EXPECT_LT(MeanTravel(With("effect.actuator_deadband_n", 1.5)), 0.7 * FreeTravel());
}

// Softening springs, statically: two lumps pulled apart by F settle where
// F = k x / sqrt(1 + (sigma x)^2), x = F / sqrt(k^2 - F^2 sigma^2). (Compression is
// symmetric in the model, but a free pair under end loads buckles: not testable this way.)
TEST(CaterpillarEffects, SofteningSpringStretchesMoreThanLinear) {
  const double sigma = 300, force = 2;
  const CaterpillarParams p = With("effect.spring_softening", sigma);
  CaterpillarSim sim(p, FreeChain(1, 2));
  Simulate(sim, 1.0, 0, [&](CaterpillarSim& s) {
    dBodyAddForce(s.body().lump(0), -force, 0, 0);
    dBodyAddForce(s.body().lump(1), force, 0, 0);
  });
  const double k = p.Link(1).axial_n_per_m;
  const double expected = force / std::sqrt(k * k - force * force * sigma * sigma);
  EXPECT_NEAR(sim.body().LinkExtension(0), expected, 0.005 * expected);
  EXPECT_GT(expected, 1.2 * force / k);  // 2.35 mm against 1.92 mm linear
}

// ---------------------------------------------------------------------------------------
// Names and ranges.

TEST(CaterpillarEffects, SetParamKnowsEveryEffectAndRejectsOutOfRange) {
  for (const std::string& name : kEffectNames) {
    EXPECT_NE(std::find(CalibratableParamNames().begin(), CalibratableParamNames().end(), name),
              CalibratableParamNames().end())
        << name;
  }
  const struct {
    const char* name;
    double bad;
  } cases[] = {{"effect.tether_force_n", -0.1},        {"effect.tether_force_n", 25},
               {"effect.tether_stiffness_n_per_m", -1}, {"effect.slope_rad", 0.31},
               {"effect.slope_rad", -0.31},             {"effect.drag_n_s_per_m", -0.01},
               {"effect.drag_n_s_per_m", 11},           {"effect.friction_forward", -0.1},
               {"effect.friction_backward", 10.5},      {"effect.actuator_lag_s", -0.001},
               {"effect.actuator_lag_s", 2},            {"effect.actuator_delay_s", 0.21},
               {"effect.actuator_delay_s", -0.01},      {"effect.spring_softening", -1},
               {"effect.spring_softening", 2000},       {"effect.slope_rad", NAN},
               {"effect.actuator_deadband_n", -0.1},    {"effect.actuator_deadband_n", 21},
               {"effect.lump_compliance_per_mpa", -1},  {"effect.lump_compliance_per_mpa", 101}};
  for (const auto& c : cases) {
    CaterpillarParams p = Params();
    const absl::Status s = SetParam(p, c.name, c.bad);
    EXPECT_FALSE(s.ok()) << c.name << " = " << c.bad;
    EXPECT_THAT(std::string(s.message()), HasSubstr(c.name));
    EXPECT_THAT(std::string(s.message()), HasSubstr("is outside"));
    EXPECT_EQ(p.effects.tether_force_n, 0);  // unchanged on error
    EXPECT_EQ(p.effects.slope_rad, 0);
  }
  CaterpillarParams p = Params();
  ASSERT_TRUE(SetParam(p, "effect.slope_rad", -0.3).ok());
  ASSERT_TRUE(SetParam(p, "effect.actuator_delay_s", 0.2).ok());
  EXPECT_EQ(p.effects.slope_rad, -0.3);
  EXPECT_EQ(p.effects.actuator_delay_s, 0.2);
}

// ---------------------------------------------------------------------------------------
// The catalog.

TEST(EffectCatalog, HasTheStableIdsInOrder) {
  std::vector<std::string> ids;
  for (const auto& e : effects::EffectCatalog()) ids.push_back(e.id);
  EXPECT_EQ(ids, (std::vector<std::string>{
                     "tether.constant", "tether.growing", "ground.slope", "friction.viscous",
                     "friction.anisotropic", "actuator.lag", "actuator.delay",
                     "actuator.force_scale", "actuator.deadband", "servo.deadband", "contact.softness",
                     "mass.offset", "stiffness.scale",
                     "spring.softening", "model.resolution", "damping.scale"}));
  for (const auto& e : effects::EffectCatalog()) {
    EXPECT_EQ(effects::FindEffect(e.id), &e);
    EXPECT_FALSE(e.name.empty() || e.meaning.empty() || e.where.empty() || e.experiment.empty())
        << e.id;
  }
  EXPECT_EQ(effects::FindEffect("no.such"), nullptr);
  for (const auto& e : effects::EffectCatalog()) EXPECT_FALSE(e.params.empty()) << e.id;
}

// Every parameter of an effect that applies to the caterpillar is a SetParam name, its
// nominal value is the model as it is, and the forward gait stays a valid simulation at
// both ends of every range. (Servo effects apply to robots with servos: generic tests.)
TEST(EffectCatalog, ParamsAreSettableAndTheirRangesSimulate) {
  std::set<std::string> seen;
  const GaitEvaluation ref = Evaluate(Params());
  const auto& cat = robots::Robot("caterpillar");
  for (const auto& e : effects::EffectCatalog()) {
    for (const auto& param : e.params) {
      EXPECT_TRUE(seen.insert(param.name).second) << param.name << " in two effects";
      EXPECT_LT(param.lo, param.hi) << param.name;
      EXPECT_GE(param.nominal, param.lo) << param.name;
      EXPECT_LE(param.nominal, param.hi) << param.name;
      if (!effects::WhyNotApplicable(e, cat).empty()) continue;
      CaterpillarParams nominal = Params();
      ASSERT_TRUE(SetParam(nominal, param.name, param.nominal).ok()) << param.name;
      EXPECT_EQ(Evaluate(nominal).distance_per_cycle_m, ref.distance_per_cycle_m)
          << e.id << ": " << param.name << " = " << param.nominal << " is not the model as it is";
      for (double v : {param.lo, param.hi}) {
        CaterpillarParams p = Params();
        const absl::Status s = SetParam(p, param.name, v);
        ASSERT_TRUE(s.ok()) << s;
        const GaitEvaluation ev = Evaluate(p);
        EXPECT_TRUE(ev.valid) << e.id << ": " << param.name << " = " << v << ": " << ev.reason;
      }
    }
  }
}

}  // namespace
}  // namespace gaitforge::caterpillar::testing
