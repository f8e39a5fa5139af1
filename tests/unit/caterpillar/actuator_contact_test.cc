// Actuators, ground contact and energy of the whole robot on the ground.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "tests/unit/caterpillar/test_helpers.h"
#include "workers/models/caterpillar/gait.h"

namespace gaitforge::caterpillar::testing {
namespace {

// Stroke limit: the speculative stops hold the length within 0.3 mm of 51..62 mm
// (ode-notes.md saw 0.3 mm for contact-joint stops at h = 1 ms).
constexpr double kStrokeTolM = 3e-4;

TEST(CaterpillarActuators, LengthStaysWithinStrokeUnderManyGaits) {
  const CaterpillarParams& p = Params();
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::vector<double>> gaits = {TravellingWaveGenes(0.8), TravellingWaveGenes(0.3)};
  for (int i = 0; i < 4; ++i) {
    std::vector<double> g(kGenes);
    for (int j = 0; j < 12; ++j) g[j] = u(rng);
    g[12] = 0.2 + 1.8 * u(rng);
    gaits.push_back(g);
  }
  for (const auto& genes : gaits) {
    const Gait gait = *Gait::FromGenes(genes);
    CaterpillarSim sim(p);
    double lo = 1, hi = 0;
    const int64_t steps = static_cast<int64_t>(2.0 / sim.timestep());
    for (int64_t n = 0; n < steps; ++n) {
      const sim::SimOutcome o = sim.Step(gait.OnMask(sim.time()));
      ASSERT_TRUE(o.ok) << o.reason;
      for (double len : sim.actuator_lengths()) {
        lo = std::min(lo, len);
        hi = std::max(hi, len);
      }
    }
    EXPECT_GE(lo, p.actuators.min_length_m - kStrokeTolM) << "T = " << genes[12];
    EXPECT_LE(hi, p.actuators.max_length_m + kStrokeTolM) << "T = " << genes[12];
  }
}

double HeldLength(const BuildOptions& options, int actuator) {
  CaterpillarSim sim(Params(), options);
  Simulate(sim, 0.5, 1u << actuator);
  for (size_t i = 0; i < sim.body().actuators().size(); ++i) {
    if (sim.body().actuators()[i].index == actuator) return sim.actuator_lengths()[i];
  }
  ADD_FAILURE() << "no actuator " << actuator;
  return 0;
}

// A top actuator held ON extends to its 62 mm stop, on the ground (the end pairs; the middle
// pair T2 is held back by the feet around it) and in free space. A bottom actuator does not:
// opening the bottom of a pair whose top is at its 51 mm stop bends the link and, through the
// large-angle geometry, stretches it; the links balance 8.8 N near 60.3 mm in free space.
TEST(CaterpillarActuators, HeldOnTopActuatorReachesMaxLength) {
  const double max = Params().actuators.max_length_m;
  BuildOptions free_space;
  free_space.gravity = false;
  free_space.ground = false;
  for (int j : {0, 2}) EXPECT_NEAR(HeldLength(BuildOptions{}, j), max, kStrokeTolM) << "T" << j + 1;
  for (int j : {0, 1, 2}) EXPECT_NEAR(HeldLength(free_space, j), max, kStrokeTolM) << "T" << j + 1;
  for (int j : {3, 4, 5}) {
    const double len = HeldLength(free_space, j);
    EXPECT_GT(len, 0.060) << "B" << j - 2;
    EXPECT_LE(len, max + kStrokeTolM) << "B" << j - 2;
  }
}

TEST(CaterpillarActuators, ReturnSpringBringsActuatorBackToMinLength) {
  const CaterpillarParams& p = Params();
  CaterpillarSim sim(p);
  Simulate(sim, 0.3, 1u << 1);  // T2 out
  Simulate(sim, 1.0, 0);
  for (double len : sim.actuator_lengths()) {
    EXPECT_NEAR(len, p.actuators.min_length_m, kStrokeTolM);
  }
}

// No slip (paper: infinite friction): after every step, the material point at the contact
// that carries a lump's friction row (its deepest corner at or below the ground) has no
// velocity along the ground (solver precision: 1e-6 m/s). The velocity is taken where the
// contact was made, as the solver constrains it.
TEST(CaterpillarContact, FeetInContactDoNotSlip) {
  const CaterpillarParams& p = Params();
  const Gait gait = *Gait::FromGenes(TravellingWaveGenes(0.8));
  CaterpillarSim sim(p);
  const double hx = p.lumps.size_x_m / 2, hz = p.lumps.size_z_m / 2;
  int checked = 0;
  double worst = 0;
  for (int64_t n = 0; n < static_cast<int64_t>(1.6 / sim.timestep()); ++n) {
    struct Foot {
      int lump;
      Vec3 arm;  // contact point minus lump centre, world frame, at contact time
    };
    std::vector<Foot> feet;
    for (int k = 0; k < 6; ++k) {
      double best = 0;
      int found = -1;
      Vec3 arm;
      const Vec3 centre = sim.body().Position(k);
      for (int c = 0; c < 4; ++c) {
        dVector3 w;
        dBodyGetRelPointPos(sim.body().lump(k), c & 1 ? hx : -hx, 0, c & 2 ? hz : -hz, w);
        if (w[2] <= 0 && (found < 0 || w[2] < best)) {
          best = w[2];
          found = c;
          arm = {w[0] - centre.x, w[1] - centre.y, w[2] - centre.z};
        }
      }
      if (found >= 0) feet.push_back({k, arm});
    }
    const sim::SimOutcome o = sim.Step(gait.OnMask(sim.time()));
    ASSERT_TRUE(o.ok) << o.reason;
    for (const Foot& f : feet) {
      const dReal* v = dBodyGetLinearVel(sim.body().lump(f.lump));
      const dReal* w = dBodyGetAngularVel(sim.body().lump(f.lump));
      const double vx = v[0] + w[1] * f.arm.z - w[2] * f.arm.y;  // (v + w x r).x
      worst = std::max(worst, std::fabs(vx));
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_LT(worst, 1e-6) << "m/s along the ground at a foot in contact";
}

// At rest with the actuators off the robot stays where it was put: no drift, no sag beyond
// the contacts' compliance, every foot down, no motion.
TEST(CaterpillarContact, RestingModelSettlesAndStays) {
  const CaterpillarParams& p = Params();
  CaterpillarSim sim(p);
  std::vector<Vec3> start;
  for (int k = 0; k < 6; ++k) start.push_back(sim.body().Position(k));
  int min_contacts = 99;
  Simulate(sim, 3.0, 0, nullptr,
      [&](CaterpillarSim& s) { min_contacts = std::min(min_contacts, s.ground_contacts()); });
  EXPECT_EQ(min_contacts, 12) << "both bottom edges of every lump stay down";
  for (int k = 0; k < 6; ++k) {
    const Vec3 x = sim.body().Position(k);
    EXPECT_NEAR(x.x, start[k].x, 1e-9) << "lump " << k + 1;
    EXPECT_NEAR(x.z, start[k].z, 1e-6) << "lump " << k + 1;
    EXPECT_NEAR(sim.body().Pitch(k), 0, 1e-6) << "lump " << k + 1;
  }
  EXPECT_LT(sim.body().KineticEnergy(), 1e-12);
}

// With the actuators off, total mechanical energy (kinetic + gravity + link and return
// springs) never rises: the only sources are the actuators. Tolerance: a rise of 2e-4 of the
// energy at switch-off over the running minimum, for the symplectic springs' bounded energy
// error and the contacts' position correction.
TEST(CaterpillarEnergy, NeverRisesWithActuatorsOff) {
  const CaterpillarParams& p = Params();
  const double g = p.simulation.gravity_m_per_s2;
  const Gait gait = *Gait::FromGenes(TravellingWaveGenes(0.8));
  CaterpillarSim sim(p);
  double ground_level = 0;  // gravitational energy at rest, taken as zero
  for (int k = 0; k < 6; ++k) ground_level += p.lumps.mass_kg * g * sim.body().Position(k).z;
  auto energy = [&] {
    return sim.body().KineticEnergy() + sim.body().PotentialEnergy(g) - ground_level;
  };
  for (int64_t n = 0; n < static_cast<int64_t>(1.0 / sim.timestep()); ++n) {
    ASSERT_TRUE(sim.Step(gait.OnMask(sim.time())).ok);
  }
  const double e0 = energy();
  ASSERT_GT(e0, 1e-3);
  double lowest = e0, worst_rise = 0;
  Simulate(sim, 1.5, 0, nullptr, [&](CaterpillarSim&) {
    const double e = energy();
    worst_rise = std::max(worst_rise, e - lowest);
    lowest = std::min(lowest, e);
  });
  EXPECT_LT(worst_rise, 2e-4 * e0) << "J, energy at switch-off " << e0 << " J";
  EXPECT_LT(lowest, 0.5 * e0) << "the dampers dissipate";
}

// Planar model: nothing acts across the x-z plane, so y, roll and yaw stay exactly zero.
TEST(CaterpillarContact, MotionStaysInThePlane) {
  const CaterpillarParams& p = Params();
  const Gait gait = *Gait::FromGenes(TravellingWaveGenes(0.5));
  CaterpillarSim sim(p);
  for (int64_t n = 0; n < static_cast<int64_t>(1.5 / sim.timestep()); ++n) {
    ASSERT_TRUE(sim.Step(gait.OnMask(sim.time())).ok);
  }
  for (int k = 0; k < 6; ++k) {
    const dReal* q = dBodyGetQuaternion(sim.body().lump(k));
    EXPECT_EQ(sim.body().Position(k).y, 0.0);
    EXPECT_EQ(q[1], 0.0);
    EXPECT_EQ(q[3], 0.0);
  }
}

}  // namespace
}  // namespace gaitforge::caterpillar::testing
