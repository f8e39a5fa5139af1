// The caterpillar's pistons, ground contact and energy on the generic builder (actuator
// type piston, plane: xz, self_contact), the whole robot on the ground or rigs cut from it
// (caterpillar_rig.h).
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "robots/onoff_waves.h"
#include "tests/unit/generic/caterpillar_rig.h"
#include "workers/models/generic/generic_gait.h"

namespace gaitforge::generic::testing {
namespace {

// Stroke limit: the speculative stops hold the length within 0.3 mm of 51..62 mm
// (ode-notes.md saw 0.3 mm for contact-joint stops at h = 1 ms).
constexpr double kStrokeTolM = 3e-4;

std::vector<double> Wave(double period) { return robots::WaveGenes(6, period, {}); }

// Steps the rig through `seconds` of a gait from its start; `after` runs after each step.
void RunGait(Rig& rig, const std::vector<double>& genes, double seconds,
             const std::function<void(Rig&)>& after = nullptr) {
  for (int64_t n = 0; n < static_cast<int64_t>(seconds / rig->timestep() + 0.5); ++n) {
    auto commands = generic::Commands(*rig.d, genes, rig->time());
    ASSERT_TRUE(commands.ok()) << commands.status();
    const sim::SimOutcome o = rig->Step(*commands);
    ASSERT_TRUE(o.ok) << o.reason;
    if (after) after(rig);
  }
}

TEST(CaterpillarPistons, LengthStaysWithinStrokeUnderManyGaits) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<std::vector<double>> gaits = {Wave(0.8), Wave(0.3)};
  for (int i = 0; i < 4; ++i) {
    std::vector<double> g(13);
    for (int j = 0; j < 12; ++j) g[j] = u(rng);
    g[12] = 0.2 + 1.8 * u(rng);
    gaits.push_back(g);
  }
  for (const auto& genes : gaits) {
    Rig rig = MakeRig();
    const double stroke = rig("actuators.max_length_m") - rig("actuators.min_length_m");
    double lo = 1, hi = -1;
    RunGait(rig, genes, 2.0, [&](Rig& r) {
      for (double e : r->piston_extensions()) {
        lo = std::min(lo, e);
        hi = std::max(hi, e);
      }
    });
    EXPECT_GE(lo, -kStrokeTolM) << "T = " << genes[12];
    EXPECT_LE(hi, stroke + kStrokeTolM) << "T = " << genes[12];
  }
}

// Piston j (T1 T2 T3 B1 B2 B3) held ON for 0.5 s on the cut: its length.
double HeldLength(const Cut& cut, int j) {
  Rig rig = MakeRig(cut);
  Simulate(rig, 0.5, 1u << j);
  const std::string name = std::string(j < 3 ? "T" : "B") + std::to_string(j % 3 + 1);
  for (size_t i = 0; i < rig.d->actuators.size(); ++i)
    if (rig.d->actuators[i].name == name)
      return rig->piston_extensions()[i] + rig("actuators.min_length_m");
  ADD_FAILURE() << "no actuator " << name;
  return 0;
}

// A top piston held ON extends to its 62 mm stop, on the ground (the end pairs; the middle
// pair T2 is held back by the feet around it) and in free space. A bottom piston does not:
// opening the bottom of a pair whose top is at its 51 mm stop bends the link and, through
// the large-angle geometry, stretches it; the links balance 8.8 N near 60.3 mm in free space.
TEST(CaterpillarPistons, HeldOnTopPistonReachesMaxLength) {
  const double max = MakeRig()("actuators.max_length_m");
  const Cut free_space{1, 6, true, false, false};
  for (int j : {0, 2}) EXPECT_NEAR(HeldLength(Cut{}, j), max, kStrokeTolM) << "T" << j + 1;
  for (int j : {0, 1, 2}) EXPECT_NEAR(HeldLength(free_space, j), max, kStrokeTolM) << "T" << j + 1;
  for (int j : {3, 4, 5}) {
    const double len = HeldLength(free_space, j);
    EXPECT_GT(len, 0.060) << "B" << j - 2;
    EXPECT_LE(len, max + kStrokeTolM) << "B" << j - 2;
  }
}

TEST(CaterpillarPistons, ReturnSpringBringsThePistonBackToMinLength) {
  Rig rig = MakeRig();
  Simulate(rig, 0.3, 1u << 1);  // T2 out
  ASSERT_GT(rig->piston_extensions()[1], 1e-3);
  Simulate(rig, 1.0, 0);
  for (double e : rig->piston_extensions()) EXPECT_NEAR(e, 0, kStrokeTolM);
}

// No slip (paper: infinite friction): after every step, the material point at the contact
// that carries a lump's friction row (its deepest corner at or below the ground) has no
// velocity along the ground (solver precision: 1e-6 m/s). The velocity is taken where the
// contact was made, as the solver constrains it.
TEST(CaterpillarContact, FeetInContactDoNotSlip) {
  Rig rig = MakeRig();
  const double hx = rig("lumps.size_x_m") / 2, hz = rig("lumps.size_z_m") / 2;
  const std::vector<double> genes = Wave(0.8);
  int checked = 0;
  double worst = 0;
  for (int64_t n = 0; n < static_cast<int64_t>(1.6 / rig->timestep()); ++n) {
    struct Foot {
      dBodyID body;
      double arm[3];  // contact point minus lump centre, world frame, at contact time
    };
    std::vector<Foot> feet;
    for (int k = 0; k < 6; ++k) {
      const dBodyID b = rig->ode_body(k);
      const dReal* centre = dBodyGetPosition(b);
      double best = 0;
      int found = -1;
      Foot foot{b, {0, 0, 0}};
      for (int c = 0; c < 4; ++c) {
        dVector3 w;
        dBodyGetRelPointPos(b, c & 1 ? hx : -hx, 0, c & 2 ? hz : -hz, w);
        if (w[2] <= 0 && (found < 0 || w[2] < best)) {
          best = w[2];
          found = c;
          for (int i = 0; i < 3; ++i) foot.arm[i] = w[i] - centre[i];
        }
      }
      if (found >= 0) feet.push_back(foot);
    }
    auto commands = generic::Commands(*rig.d, genes, rig->time());
    ASSERT_TRUE(commands.ok());
    ASSERT_TRUE(rig->Step(*commands).ok);
    for (const Foot& f : feet) {
      const dReal* v = dBodyGetLinearVel(f.body);
      const dReal* w = dBodyGetAngularVel(f.body);
      const double vx = v[0] + w[1] * f.arm[2] - w[2] * f.arm[1];  // (v + w x r).x
      worst = std::max(worst, std::fabs(vx));
      ++checked;
    }
  }
  EXPECT_GT(checked, 1000);
  EXPECT_LT(worst, 1e-6) << "m/s along the ground at a foot in contact";
}

// At rest with the pistons off the robot stays where it was put: no drift, no sag beyond
// the contacts' compliance, every foot down, no motion.
TEST(CaterpillarContact, RestingRobotSettlesAndStays) {
  Rig rig = MakeRig();
  std::vector<std::array<double, 3>> start;
  for (int k = 0; k < 6; ++k) start.push_back(rig->BodyCentre(k));
  int min_contacts = 99;
  Simulate(rig, 3.0, 0, nullptr,
           [&](Rig& r) { min_contacts = std::min(min_contacts, r->ground_contacts()); });
  EXPECT_EQ(min_contacts, 12) << "both bottom edges of every lump stay down";
  for (int k = 0; k < 6; ++k) {
    EXPECT_NEAR(rig->BodyCentre(k)[0], start[k][0], 1e-9) << "lump " << k + 1;
    EXPECT_NEAR(rig->BodyCentre(k)[2], start[k][2], 1e-6) << "lump " << k + 1;
    EXPECT_NEAR(Pitch(rig->ode_body(k)), 0, 1e-6) << "lump " << k + 1;
  }
  EXPECT_LT(KineticEnergy(*rig.world), 1e-12);
}

// Potential energy (J): gravity above the ground, the links' axial and bending springs and
// the pistons' return springs.
double PotentialEnergy(const Rig& rig) {
  const double g = rig("simulation.gravity_m_per_s2");
  double e = 0;
  for (int i = 0; i < rig->ode_body_count(); ++i) {
    dMass m;
    dBodyGetMass(rig->ode_body(i), &m);
    e += m.mass * g * dBodyGetPosition(rig->ode_body(i))[2];
  }
  for (size_t k = 0; k < rig.d->joints.size(); ++k) {
    const auto& j = rig.d->joints[k];
    const double x = rig->LinkExtension(static_cast<int>(k)), th = rig->LinkBend(static_cast<int>(k));
    e += 0.5 * rig.Value(*j.axial_stiffness) * x * x + 0.5 * rig.Value(*j.stiffness) * th * th;
  }
  for (double s : rig->piston_extensions()) e += 0.5 * rig("actuators.return_spring_n_per_m") * s * s;
  return e;
}

// With the pistons off, total mechanical energy (kinetic, gravity, link and return
// springs) never rises: the only sources are the pistons. Tolerance: a rise of 2e-4 of the
// energy at switch-off over the running minimum, for the symplectic springs' bounded energy
// error and the contacts' position correction.
TEST(CaterpillarEnergy, NeverRisesWithThePistonsOff) {
  Rig rig = MakeRig();
  const double rest = PotentialEnergy(rig);  // taken as zero
  auto energy = [&] { return KineticEnergy(*rig.world) + PotentialEnergy(rig) - rest; };
  RunGait(rig, Wave(0.8), 1.0);
  const double e0 = energy();
  ASSERT_GT(e0, 1e-3);
  double lowest = e0, worst_rise = 0;
  Simulate(rig, 1.5, 0, nullptr, [&](Rig&) {
    const double e = energy();
    worst_rise = std::max(worst_rise, e - lowest);
    lowest = std::min(lowest, e);
  });
  EXPECT_LT(worst_rise, 2e-4 * e0) << "J, energy at switch-off " << e0 << " J";
  EXPECT_LT(lowest, 0.5 * e0) << "the dampers dissipate";
}

// Planar robot: nothing acts across the x-z plane, so y, roll and yaw stay exactly zero.
TEST(CaterpillarContact, MotionStaysInThePlane) {
  Rig rig = MakeRig();
  RunGait(rig, Wave(0.5), 1.5);
  for (int k = 0; k < 6; ++k) {
    const dReal* q = dBodyGetQuaternion(rig->ode_body(k));
    EXPECT_EQ(rig->BodyCentre(k)[1], 0.0);
    EXPECT_EQ(q[1], 0.0);
    EXPECT_EQ(q[3], 0.0);
  }
}

}  // namespace
}  // namespace gaitforge::generic::testing
