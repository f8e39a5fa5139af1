// The soft caterpillar built by the generic builder from its descriptor's structure (spring
// links, pistons, the planar ground, self-contacts) steps bit for bit as its dedicated model
// does: the first step of moving it onto the generic builder (issue 23).
#include <cstdint>
#include <random>
#include <vector>

#include "gtest/gtest.h"
#include "robots/registry.h"
#include "workers/models/caterpillar/calibration_objective.h"
#include "workers/models/caterpillar/caterpillar_eval.h"
#include "workers/models/caterpillar/caterpillar_params.h"
#include "workers/models/caterpillar/caterpillar_sim.h"
#include "workers/models/caterpillar/gait.h"
#include "workers/models/caterpillar/param_overrides.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/models/generic/generic_world.h"

namespace gaitforge::generic {
namespace {

const robots::RobotDescriptor& Caterpillar() { return robots::Robot("caterpillar"); }

// Genotypes: the paper's travelling waves and random gaits over the gene space.
std::vector<std::vector<double>> Gaits(int random_count) {
  std::vector<std::vector<double>> out;
  for (double period : {0.4, 0.8, 1.5})
    for (const auto& shape : caterpillar::WaveFamily())
      out.push_back(caterpillar::WaveGenes(period, shape));
  std::mt19937_64 rng(23);
  for (int i = 0; i < random_count; ++i) {
    std::vector<double> g;
    for (const robots::Gene& gene : Caterpillar().controller.genes)
      g.push_back(std::uniform_real_distribution<double>(gene.lo, gene.hi)(rng));
    out.push_back(g);
  }
  return out;
}

TEST(CaterpillarPort, EveryBodyFollowsTheDedicatedModelBitForBit) {
  const auto& d = Caterpillar();
  ParamValues values(d);
  auto world = GenericWorld::Build(d, values, 0);
  ASSERT_TRUE(world.ok()) << world.status();
  caterpillar::CaterpillarSim sim(caterpillar::DefaultCaterpillarParams());
  ASSERT_EQ((*world)->body_count(), sim.body().body_count());
  const std::vector<double> genes = caterpillar::TravellingWaveGenes(0.8);
  auto gait = caterpillar::Gait::FromGenes(genes);
  ASSERT_TRUE(gait.ok());
  int64_t contacts = 0;
  for (int n = 0; n < 3000; ++n) {  // three gait cycles
    const double t = sim.time();
    auto commands = Commands(d, genes, t);
    ASSERT_TRUE(commands.ok()) << commands.status();
    ASSERT_TRUE(sim.Step(gait->OnMask(t)).ok);
    ASSERT_TRUE((*world)->Step(*commands).ok);
    ASSERT_EQ((*world)->ground_contacts(), sim.ground_contacts()) << "step " << n;
    contacts += sim.ground_contacts();
    for (int b = 0; b < sim.body().body_count(); ++b) {
      for (int k = 0; k < 3; ++k) {
        auto channel = (*world)->Channel("m" + std::to_string(b + 1) + "." + "xyz"[k]);
        ASSERT_TRUE(channel.ok());
        const caterpillar::Vec3 m = sim.body().Marker(b);
        ASSERT_EQ(*channel, k == 0 ? m.x : k == 1 ? m.y : m.z) << "step " << n << " body " << b;
      }
    }
  }
  EXPECT_GT(contacts, 0);
  // The gait moved the robot: the comparison was not of two bodies at rest.
  EXPECT_GT(std::fabs((*world)->CentreOfMass()[0] - 2.5 * d.Value("lumps.spacing_m")), 1e-3);
}

TEST(CaterpillarPort, GaitFitnessIsBitIdenticalToTheDedicatedModel) {
  const auto& d = Caterpillar();
  ParamValues values(d);
  int valid = 0;
  for (const auto& genes : Gaits(12)) {
    auto gait = caterpillar::Gait::FromGenes(genes);
    ASSERT_TRUE(gait.ok());
    const caterpillar::GaitEvaluation want =
        caterpillar::EvaluateGait(caterpillar::DefaultCaterpillarParams(), *gait);
    const GaitResult got = EvaluateGait(d, values, genes);
    ASSERT_EQ(got.valid, want.valid) << got.reason << " / " << want.reason;
    EXPECT_EQ(got.distance_per_cycle_m, want.distance_per_cycle_m);
    if (want.valid) {  // the paper objective's metrics, also bit for bit
      EXPECT_EQ(got.max_body_pitch_rad, want.max_body_pitch_rad);
      EXPECT_EQ(got.max_stroke_m, want.max_stroke_m);
      EXPECT_EQ(got.piston_work_j, want.actuator_energy_j);
      EXPECT_EQ(got.airborne_fraction, want.airborne_fraction);
    }
    valid += want.valid;
  }
  EXPECT_GT(valid, 20);
}

// A recording simulated by the generic build (gaitforge-sim trajectory) holds the markers
// the dedicated model sampled: the measured cycles after settling, times from rest.
TEST(CaterpillarPort, SimulatedRecordingsMatchTheDedicatedModel) {
  const auto& d = Caterpillar();
  const ParamValues values(d);
  const std::vector<double> genes = caterpillar::WaveGenes(0.354, caterpillar::WaveFamily()[2]);
  caterpillar::EvalOptions o;
  o.settle_cycles = 2;
  o.measured_cycles = 3;
  o.marker_rate_hz = 100;
  const auto want = caterpillar::EvaluateGait(caterpillar::DefaultCaterpillarParams(),
                                              *caterpillar::Gait::FromGenes(genes), o);
  const auto got = SimulateChannels(d, values, genes, 3, 100, 0, {}, 2);
  ASSERT_TRUE(want.valid && got.valid) << got.reason;
  ASSERT_EQ(got.trajectory.t, want.markers.t);
  const auto dedicated = caterpillar::MarkerChannels(want.markers);
  ASSERT_EQ(got.trajectory.channels, dedicated.channels);
  EXPECT_EQ(got.trajectory.columns, dedicated.columns);
  EXPECT_NEAR(got.trajectory.t.front(), 2 * 0.354, 1e-3);
}

// Each candidate effect the builder attaches, set on both builds: the same fitness (the
// delay and lag of the pistons, their deadband, the links' softening, the tether, drag,
// slope and direction-dependent friction).
TEST(CaterpillarPort, EffectsAgreeWithTheDedicatedModel) {
  const auto& d = Caterpillar();
  const std::vector<std::vector<std::pair<std::string, double>>> cases = {
      {{"effect.tether_force_n", 0.6}},
      {{"effect.tether_stiffness_n_per_m", 12}},
      {{"effect.slope_rad", 0.08}},
      {{"effect.drag_n_s_per_m", 0.7}},
      {{"effect.friction_forward", 0.4}, {"effect.friction_backward", 0.9}},
      {{"effect.actuator_lag_s", 0.03}},
      {{"effect.actuator_delay_s", 0.0237}},
      {{"effect.actuator_delay_s", 0.01}, {"effect.actuator_lag_s", 0.01}},
      {{"effect.actuator_deadband_n", 1.2}},
      {{"effect.spring_softening", 150}},
      {{"effect.lump_compliance_per_mpa", 6}},
      {{"effect.lump_compliance_per_mpa", 9}, {"effect.tether_force_n", 0.4}},
  };
  const auto gaits = Gaits(2);
  for (const auto& set : cases) {
    caterpillar::CaterpillarParams params = caterpillar::DefaultCaterpillarParams();
    ParamValues values(d);
    for (const auto& [name, value] : set) {
      ASSERT_TRUE(caterpillar::SetParam(params, name, value).ok()) << name;
      ASSERT_TRUE(values.Set(name, value).ok()) << name;
    }
    int differ = 0;  // gaits whose travel the effect changed
    for (size_t g = 0; g < gaits.size(); g += 6) {
      auto gait = caterpillar::Gait::FromGenes(gaits[g]);
      const auto want = caterpillar::EvaluateGait(params, *gait);
      const GaitResult got = EvaluateGait(d, values, gaits[g]);
      ASSERT_EQ(got.valid, want.valid) << set[0].first << ": " << got.reason << " / " << want.reason;
      // Split lumps: the same motion, their centres averaged in another order.
      if (values.Effect("effect.lump_compliance_per_mpa") > 0) {
        EXPECT_NEAR(got.distance_per_cycle_m, want.distance_per_cycle_m, 1e-15) << "gait " << g;
      } else {
        EXPECT_EQ(got.distance_per_cycle_m, want.distance_per_cycle_m) << set[0].first << " gait " << g;
      }
      const auto plain = caterpillar::EvaluateGait(caterpillar::DefaultCaterpillarParams(), *gait);
      differ += plain.distance_per_cycle_m != want.distance_per_cycle_m;
    }
    EXPECT_GT(differ, 0) << set[0].first << " changed nothing";
  }
}

}  // namespace
}  // namespace gaitforge::generic
