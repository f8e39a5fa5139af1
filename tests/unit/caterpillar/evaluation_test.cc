// The evaluation: the gait controller, timestep convergence, divergence handling,
// determinism across threads, and the "caterpillar.distance" objective.
#include <cmath>
#include <cstring>
#include <random>
#include <thread>
#include <vector>

#include "gmock/gmock.h"
#include "services/core/objective_catalog.h"
#include "tests/unit/caterpillar/test_helpers.h"
#include "workers/models/caterpillar/caterpillar_eval.h"
#include "workers/models/caterpillar/caterpillar_objective.h"
#include "workers/models/caterpillar/gait.h"

namespace gaitforge::caterpillar::testing {
namespace {

using ::testing::HasSubstr;

TEST(CaterpillarGait, OnWhilePhaseInActivationWindowWrappingRound) {
  // T1 on [0.2, 0.5); T2 on [0.8, 1) and [0, 0.1) (wraps); T3 never (a == d).
  std::vector<double> g = {0.2, 0.8, 0.3, 0, 0, 0, 0.5, 0.1, 0.3, 0, 0, 0, 2.0};
  const Gait gait = *Gait::FromGenes(g);
  EXPECT_EQ(gait.OnMask(0.0), 0b010u);
  EXPECT_EQ(gait.OnMask(0.39), 0b000u);   // phase 0.195
  EXPECT_EQ(gait.OnMask(0.4), 0b001u);    // phase 0.2: on at a_j
  EXPECT_EQ(gait.OnMask(0.99), 0b001u);
  EXPECT_EQ(gait.OnMask(1.0), 0b000u);    // phase 0.5: off at d_j
  EXPECT_EQ(gait.OnMask(1.7), 0b010u);    // phase 0.85
  EXPECT_EQ(gait.OnMask(2.1), 0b010u);    // next cycle, phase 0.05
  EXPECT_EQ(gait.OnMask(2.5), 0b001u);    // phase 0.25
}

TEST(CaterpillarGait, RejectsWrongGenotypes) {
  EXPECT_FALSE(Gait::FromGenes({0.1, 0.2}).ok());
  std::vector<double> g = TravellingWaveGenes(0.8);
  g[12] = 0.01;
  EXPECT_FALSE(Gait::FromGenes(g).ok());
  g[12] = 0.8;
  g[3] = NAN;
  EXPECT_FALSE(Gait::FromGenes(g).ok());
}

// Convergence in the timestep. The robot hops under 8.8 N steps, so a whole gait's travel is
// sensitive to any numerical change (../shared/robots/caterpillar.md); a gentle motion
// converges: one top actuator's stroke and return (no hop), forward travel of the body
// centre after 0.6 s. Tolerances: 1 ms within 0.3 mm and 0.5 ms within 0.05 mm of 0.25 ms.
TEST(CaterpillarConvergence, GentleMotionConvergesAsTimestepHalves) {
  const CaterpillarParams& p = Params();
  auto travel = [&](int actuator, double h) {
    CaterpillarSim sim(p, BuildOptions{}, h);
    const double x0 = MeanX(sim.body());
    Simulate(sim, 0.3, 1u << actuator);
    Simulate(sim, 0.3, 0);
    return MeanX(sim.body()) - x0;
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
// reported invalid with a reason; the process goes on.
TEST(CaterpillarDivergence, UnstableParametersGiveInvalidResult) {
  CaterpillarParams p = Params();
  p.links.flexure.axial_n_per_m = 1e6;
  p.links.segment.axial_n_per_m = 1e6;
  p.links.axial_damping_ratio = 0.01;
  p.simulation.timestep_s = 0.002;
  const GaitEvaluation e = EvaluateGait(p, *Gait::FromGenes(TravellingWaveGenes(0.8)));
  EXPECT_FALSE(e.valid);
  EXPECT_THAT(e.reason, HasSubstr("diverged"));
  EXPECT_THAT(e.reason, HasSubstr("h*omega_max"));
  // The next evaluation in this thread is unaffected.
  EXPECT_TRUE(EvaluateGait(Params(), *Gait::FromGenes(TravellingWaveGenes(0.8))).valid);
}

// The objective catalog states the model file's defaults (the spec validator and the
// report's timestep check read them there); they must be caterpillar.yaml's.
TEST(CaterpillarEvaluation, CatalogDefaultsAreTheModelFiles) {
  const auto& sim = Params().simulation;
  for (const char* objective : {"caterpillar.distance", "caterpillar.calibration"}) {
    const core::ObjectiveInfo* info = core::FindObjective(objective);
    ASSERT_NE(info, nullptr) << objective;
    for (const auto& p : info->params) {
      if (p.name == "timestep_ms") {
        EXPECT_DOUBLE_EQ(p.default_value * 1e-3, sim.timestep_s);
      }
      if (p.name == "settle_cycles") {
        EXPECT_EQ(p.default_value, sim.settle_cycles);
      }
      if (p.name == "cycles") {
        EXPECT_EQ(p.default_value, sim.measured_cycles);
      }
    }
  }
}

TEST(CaterpillarEvaluation, MetricsAreConsistent) {
  EvalOptions o;
  o.measured_cycles = 2;
  o.marker_rate_hz = 100;
  const GaitEvaluation e = EvaluateGait(Params(), *Gait::FromGenes(TravellingWaveGenes(0.8)), o);
  ASSERT_TRUE(e.valid) << e.reason;
  EXPECT_NEAR(e.simulated_s, 4 * 0.8, 1e-9);
  EXPECT_GT(e.actuator_energy_j, 0);
  EXPECT_NEAR(e.max_stroke_m, 0.011, 3e-4);
  EXPECT_GE(e.airborne_fraction, 0);
  EXPECT_LE(e.airborne_fraction, 1);
  // 1.6 s at 100 Hz: 161 samples, the first at the start of the measured cycles.
  ASSERT_EQ(e.markers.t.size(), 161u);
  EXPECT_NEAR(e.markers.t.front(), 1.6, 1e-9);
  EXPECT_NEAR(e.markers.t.back(), 3.2, 1e-9);
  EXPECT_EQ(e.markers.y[3].back(), 0.0);
}

TEST(CaterpillarEvaluation, MarkersSitAtTopFaceCentres) {
  const CaterpillarParams& p = Params();
  CaterpillarSim sim(p);
  for (int k = 0; k < 6; ++k) {
    const Vec3 m = sim.body().Marker(k);
    EXPECT_DOUBLE_EQ(m.x, k * p.lumps.spacing_m);
    EXPECT_DOUBLE_EQ(m.z, p.lumps.size_z_m);
  }
}

objectives::EvalInput Input(std::vector<double> genes) {
  objectives::EvalInput in;
  in.genes = std::move(genes);
  in.params = {{"cycles", 1}, {"settle_cycles", 1}};
  return in;
}

std::vector<std::vector<double>> SomeGaits() {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::vector<double>> gaits = {TravellingWaveGenes(0.8)};
  for (int i = 0; i < 3; ++i) {
    std::vector<double> g(kGenes);
    for (int j = 0; j < 12; ++j) g[j] = u(rng);
    g[12] = 0.2 + 0.6 * u(rng);
    gaits.push_back(g);
  }
  return gaits;
}

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

TEST(CaterpillarObjective, ThreadsGiveBitIdenticalResults) {
  const CaterpillarObjective objective(Params());
  const auto gaits = SomeGaits();
  std::vector<objectives::EvalResult> sequential;
  for (const auto& g : gaits) sequential.push_back(objective.Evaluate(Input(g)));
  std::vector<objectives::EvalResult> a(gaits.size()), b(gaits.size());
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
      EXPECT_TRUE(SameBits(a[i].metrics.at(name), value)) << name;
      EXPECT_TRUE(SameBits(b[i].metrics.at(name), value)) << name;
    }
  }
}

TEST(CaterpillarObjective, ParamsAreCheckedAndMetricsReported) {
  const CaterpillarObjective objective(Params());
  auto in = Input(TravellingWaveGenes(0.8));
  const auto r = objective.Evaluate(in);
  ASSERT_TRUE(r.valid) << r.reason;
  EXPECT_EQ(r.fitness, r.metrics.at("distance_per_cycle"));
  for (const char* m : {"max_body_pitch", "max_stroke", "actuator_energy", "airborne_fraction"}) {
    EXPECT_TRUE(r.metrics.count(m)) << m;
  }
  in.params["cycles"] = 51;
  EXPECT_THAT(objective.Evaluate(in).reason, HasSubstr("cycles"));
  in.params["cycles"] = 1;
  in.params["timestep_ms"] = 5;
  EXPECT_THAT(objective.Evaluate(in).reason, HasSubstr("timestep_ms"));
  in.params.erase("timestep_ms");
  in.params["speed"] = 1;
  EXPECT_THAT(objective.Evaluate(in).reason, HasSubstr("unknown param speed"));
  in.params.erase("speed");
  in.genes.pop_back();
  EXPECT_THAT(objective.Evaluate(in).reason, HasSubstr("13 genes"));
}

TEST(CaterpillarObjective, RegistersUnderItsCatalogName) {
  objectives::ObjectiveRegistry registry;
  RegisterCaterpillar(registry);
  EXPECT_NE(registry.Find("caterpillar.distance"), nullptr);
}

}  // namespace
}  // namespace gaitforge::caterpillar::testing
