// The caterpillar's evaluation on the generic builder: its on/off gait, timestep
// convergence, divergence as a result, its metrics and markers, the paper objective
// (caterpillar.distance) from the worker's registry, threads and robust evaluation.
#include <cmath>
#include <cstring>
#include <random>
#include <thread>
#include <vector>

#include "gmock/gmock.h"
#include "robots/controllers.h"
#include "robots/onoff_waves.h"
#include "robots/registry.h"
#include "services/core/objective_catalog.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/models/generic/generic_world.h"
#include "workers/objectives/ensemble.h"
#include "workers/models/generic/generic_objective.h"

namespace gaitforge::generic {
namespace {

using ::testing::HasSubstr;

const robots::RobotDescriptor& Caterpillar() { return robots::Robot("caterpillar"); }
std::vector<double> Wave(double period) { return robots::WaveGenes(6, period, {}); }

TEST(CaterpillarGait, OnWhilePhaseInActivationWindowWrappingRound) {
  // T1 on [0.2, 0.5); T2 on [0.8, 1) and [0, 0.1) (wraps); T3 never (a == d).
  const std::vector<double> g = {0.2, 0.8, 0.3, 0, 0, 0, 0.5, 0.1, 0.3, 0, 0, 0, 2.0};
  auto on = [&](double t) {
    const auto c = *Commands(Caterpillar(), g, t);
    return std::vector<double>(c.begin(), c.begin() + 3);
  };
  using V = std::vector<double>;
  EXPECT_EQ(on(0.0), (V{0, 1, 0}));
  EXPECT_EQ(on(0.39), (V{0, 0, 0}));  // phase 0.195
  EXPECT_EQ(on(0.4), (V{1, 0, 0}));   // phase 0.2: on at a_j
  EXPECT_EQ(on(0.99), (V{1, 0, 0}));
  EXPECT_EQ(on(1.0), (V{0, 0, 0}));   // phase 0.5: off at d_j
  EXPECT_EQ(on(1.7), (V{0, 1, 0}));   // phase 0.85
  EXPECT_EQ(on(2.1), (V{0, 1, 0}));   // next cycle, phase 0.05
  EXPECT_EQ(on(2.5), (V{1, 0, 0}));   // phase 0.25
}

TEST(CaterpillarGait, WrongGenotypesAreRefusedWithTheReason) {
  EXPECT_THAT(std::string(Commands(Caterpillar(), {0.1, 0.2}, 0).status().message()),
              HasSubstr("takes 13 genes, got 2"));
  std::vector<double> g = Wave(0.8);
  g[12] = 0.01;
  EXPECT_THAT(std::string(Commands(Caterpillar(), g, 0).status().message()),
              HasSubstr("gait period T = 0.01 s is outside [0.05, 10] s"));
  g[12] = 0.8;
  g[3] = NAN;
  EXPECT_THAT(std::string(Commands(Caterpillar(), g, 0).status().message()),
              HasSubstr("gene 3 (a_B1) is not finite"));
  const GaitResult r = EvaluateGait(Caterpillar(), ParamValues(Caterpillar()), g);
  EXPECT_FALSE(r.valid);
  EXPECT_THAT(r.reason, HasSubstr("not finite"));
}

// Convergence in the timestep. The robot hops under 8.8 N steps, so a whole gait's travel is
// sensitive to any numerical change (../shared/robots/caterpillar.md); a gentle motion
// converges: one top actuator's stroke and return (no hop), forward travel of the body
// centre after 0.6 s. Tolerances: 1 ms within 0.3 mm and 0.5 ms within 0.05 mm of 0.25 ms.
TEST(CaterpillarConvergence, GentleMotionConvergesAsTimestepHalves) {
  const ParamValues values(Caterpillar());
  auto travel = [&](int actuator, double h) {
    auto world = GenericWorld::Build(Caterpillar(), values, h);
    EXPECT_TRUE(world.ok());
    const double x0 = (*world)->CentreOfMass()[0];
    std::vector<double> commands(6, 0.0);
    commands[actuator] = 1;
    const auto steps = std::llround(0.3 / h);
    for (int64_t i = 0; i < 2 * steps; ++i) {
      if (i == steps) commands[actuator] = 0;
      EXPECT_TRUE((*world)->Step(commands).ok);
    }
    return (*world)->CentreOfMass()[0] - x0;
  };
  for (int actuator : {0, 2}) {  // T1, T3
    const double d1 = travel(actuator, 1e-3), d2 = travel(actuator, 5e-4),
                 d4 = travel(actuator, 2.5e-4);
    EXPECT_GT(std::fabs(d4), 1e-4) << "the pulse moves the body";
    EXPECT_NEAR(d1, d4, 3e-4) << "actuator " << actuator;
    EXPECT_NEAR(d2, d4, 5e-5) << "actuator " << actuator;
  }
}

// A deliberately unstable model (links of 1e6 N/m, damping 0.01 of critical, h = 2 ms:
// h omega = 16, beyond the spring integration's limit (h omega)^2 < 4 + 4 zeta h omega) is
// an invalid result with a reason; the next evaluation is unaffected.
TEST(CaterpillarDivergence, UnstableParametersGiveInvalidResult) {
  ParamValues v(Caterpillar());
  for (const auto& [name, value] : std::vector<std::pair<std::string, double>>{
           {"links.flexure.axial_stiffness_n_per_m", 1e6},
           {"links.segment.axial_stiffness_n_per_m", 1e6},
           {"links.axial_damping_ratio", 0.01},
           {"simulation.timestep_s", 0.002}})
    ASSERT_TRUE(v.Set(name, value).ok()) << name;
  const GaitResult e = EvaluateGait(Caterpillar(), v, Wave(0.8));
  EXPECT_FALSE(e.valid);
  EXPECT_THAT(e.reason, AnyOf(HasSubstr("moves at"), HasSubstr("spins at"), HasSubstr("NaN"),
                              HasSubstr("beyond its stroke"), HasSubstr("ODE")));
  EXPECT_TRUE(EvaluateGait(Caterpillar(), ParamValues(Caterpillar()), Wave(0.8)).valid);
}

// The objective catalog states the descriptor's defaults (the spec validator and the
// report's timestep check read them there).
TEST(CaterpillarEvaluation, CatalogDefaultsAreTheDescriptors) {
  const auto& d = Caterpillar();
  for (const char* objective : {"caterpillar.distance", "caterpillar.calibration"}) {
    const core::ObjectiveInfo* info = core::FindObjective(objective);
    ASSERT_NE(info, nullptr) << objective;
    for (const auto& p : info->params) {
      if (p.name == "timestep_ms") {
        EXPECT_DOUBLE_EQ(p.default_value * 1e-3, d.Value("simulation.timestep_s"));
      } else if (p.name == "settle_cycles") {
        EXPECT_EQ(p.default_value, d.Value("simulation.settle_cycles"));
      } else if (p.name == "cycles") {
        EXPECT_EQ(p.default_value, d.Value("simulation.measured_cycles"));
      }
    }
  }
}

TEST(CaterpillarEvaluation, MetricsAndMarkersAreConsistent) {
  GaitOptions o;
  o.measured_cycles = 2;
  const GaitResult e = EvaluateGait(Caterpillar(), ParamValues(Caterpillar()), Wave(0.8), o);
  ASSERT_TRUE(e.valid) << e.reason;
  EXPECT_NEAR(e.simulated_s, 4 * 0.8, 1e-9);
  EXPECT_GT(e.piston_work_j, 0);
  EXPECT_NEAR(e.max_stroke_m, 0.011, 3e-4);
  EXPECT_GE(e.airborne_fraction, 0);
  EXPECT_LE(e.airborne_fraction, 1);
  // 1.6 s at 100 Hz: 161 samples, the first at the start of the measured cycles.
  const auto run = SimulateChannels(Caterpillar(), ParamValues(Caterpillar()), Wave(0.8), 2, 100,
                                    0, {}, 2);
  ASSERT_EQ(run.trajectory.t.size(), 161u);
  EXPECT_NEAR(run.trajectory.t.front(), 1.6, 1e-9);
  EXPECT_NEAR(run.trajectory.t.back(), 3.2, 1e-9);
  EXPECT_EQ(run.trajectory.columns[3 * 3 + 1].back(), 0.0);  // m4.y: the robot stays planar
}

TEST(CaterpillarEvaluation, MarkersSitAtTopFaceCentres) {
  const auto& d = Caterpillar();
  auto world = GenericWorld::Build(d, ParamValues(d), 0);
  ASSERT_TRUE(world.ok());
  for (int k = 0; k < 6; ++k) {
    EXPECT_DOUBLE_EQ(*(*world)->Channel("m" + std::to_string(k + 1) + ".x"),
                     k * d.Value("lumps.spacing_m"));
    EXPECT_DOUBLE_EQ(*(*world)->Channel("m" + std::to_string(k + 1) + ".z"), d.Value("lumps.size_z_m"));
  }
}

objectives::EvalInput Input(std::vector<double> genes) {
  objectives::EvalInput in;
  in.genes = std::move(genes);
  in.params = {{"cycles", 1}, {"settle_cycles", 1}};
  return in;
}

// caterpillar.distance as gaitforge-worker registers it (workers/worker/registry.cc).
const objectives::Objective& PaperObjective() {
  static const objectives::ObjectiveRegistry* registry = [] {
    auto* r = new objectives::ObjectiveRegistry;
    RegisterRobotObjective(*r, "caterpillar.distance", kRobotDistanceName, "caterpillar");
    return r;
  }();
  return *registry->Find("caterpillar.distance");
}

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(CaterpillarObjective, ThreadsGiveBitIdenticalResults) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::vector<double>> gaits = {Wave(0.8)};
  for (int i = 0; i < 3; ++i) {
    std::vector<double> g(13);
    for (int j = 0; j < 12; ++j) g[j] = u(rng);
    g[12] = 0.2 + 0.6 * u(rng);
    gaits.push_back(g);
  }
  const auto& objective = PaperObjective();
  std::vector<objectives::EvalResult> sequential, a(gaits.size()), b(gaits.size());
  for (const auto& g : gaits) sequential.push_back(objective.Evaluate(Input(g)));
  std::thread ta([&] {
    for (size_t i = 0; i < gaits.size(); ++i) a[i] = objective.Evaluate(Input(gaits[i]));
  });
  std::thread tb([&] {
    for (size_t i = gaits.size(); i-- > 0;) b[i] = objective.Evaluate(Input(gaits[i]));
  });
  ta.join();
  tb.join();
  for (size_t i = 0; i < gaits.size(); ++i) {
    ASSERT_TRUE(sequential[i].valid) << sequential[i].reason;
    EXPECT_TRUE(SameBits(a[i].fitness, sequential[i].fitness)) << i;
    EXPECT_TRUE(SameBits(b[i].fitness, sequential[i].fitness)) << i;
    for (const auto& [name, value] : sequential[i].metrics) {
      if (std::isnan(value)) continue;  // cost of transport of a gait going backwards
      EXPECT_TRUE(SameBits(a[i].metrics.at(name), value)) << name;
      EXPECT_TRUE(SameBits(b[i].metrics.at(name), value)) << name;
    }
  }
}

TEST(CaterpillarObjective, ParamsAreCheckedAndThePapersMetricsReported) {
  const auto& objective = PaperObjective();
  auto in = Input(Wave(0.8));
  const auto r = objective.Evaluate(in);
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_EQ(r.fitness, r.metrics.at("distance_per_cycle"));
  for (const char* m : {"max_body_pitch", "max_stroke", "actuator_energy", "airborne_fraction"})
    EXPECT_TRUE(r.metrics.count(m)) << m;
  in.params["cycles"] = 1.5;
  EXPECT_THAT(objective.Evaluate(in).reason, HasSubstr("cycles"));
  in.params["cycles"] = 1;
  in.params["timestep_ms"] = -5;
  EXPECT_THAT(objective.Evaluate(in).reason, HasSubstr("timestep_ms"));
  in.params.erase("timestep_ms");
  in.params["speed"] = 1;
  EXPECT_THAT(objective.Evaluate(in).reason, HasSubstr("unknown param speed"));
  in.params.erase("speed");
  in.genes.pop_back();
  EXPECT_THAT(objective.Evaluate(in).reason, HasSubstr("takes 13 genes"));
}

// Robust evaluation (docs/objectives.md): start phase 0 is the paper's evaluation bit for
// bit; the ensemble runs each member on the model and does not depend on the thread.
TEST(CaterpillarRobust, StartPhaseZeroIsThePapersEvaluationAndOtherPhasesDiffer) {
  const auto& objective = PaperObjective();
  objectives::EvalInput in = Input(Wave(0.8));
  const auto plain = objective.Evaluate(in);
  in.params["start_phase"] = 0;
  const auto zero = objective.Evaluate(in);
  in.params["start_phase"] = 0.5;
  const auto half = objective.Evaluate(in);
  ASSERT_TRUE(plain.valid && half.valid);
  EXPECT_EQ(plain.fitness, zero.fitness);
  EXPECT_NE(plain.fitness, half.fitness);
  in.params["start_phase"] = 1.5;
  EXPECT_THAT(objective.Evaluate(in).reason, HasSubstr("start_phase = 1.5 is outside [0, 1]"));
}

TEST(CaterpillarRobust, TheEnsembleRunsEachMemberOnTheModelAndIgnoresTheThread) {
  const auto& objective = PaperObjective();
  objectives::EnsembleSpec spec;
  spec.members = 4;
  spec.numerics = {"", "simulation.timestep_s=0.0005"};
  spec.start_phases = 2;
  spec.seed = 5;
  const auto r = objectives::EvaluateEnsemble(objective, Input(Wave(0.8)), spec);
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_EQ(r.metrics.at("member.0"), objective.Evaluate(Input(Wave(0.8))).fitness);
  EXPECT_EQ(r.metrics.at("robust.members"), 4);
  EXPECT_DOUBLE_EQ(r.fitness, (r.metrics.at("member.0") + r.metrics.at("member.1") +
                               r.metrics.at("member.2") + r.metrics.at("member.3")) / 4);
  spec.parameters = {{"actuators.force_n", 8, 9.5}};
  objectives::EvalResult a, b;
  std::thread t1([&] { a = objectives::EvaluateEnsemble(objective, Input(Wave(0.8)), spec); });
  std::thread t2([&] { b = objectives::EvaluateEnsemble(objective, Input(Wave(0.8)), spec); });
  t1.join();
  t2.join();
  ASSERT_TRUE(a.valid) << a.reason;
  EXPECT_EQ(a.fitness, b.fitness);
  EXPECT_EQ(a.metrics.at("member.1"), b.metrics.at("member.1"));
  EXPECT_NE(a.metrics.at("member.0"), r.metrics.at("member.0"));  // the force was sampled
}

}  // namespace
}  // namespace gaitforge::generic
