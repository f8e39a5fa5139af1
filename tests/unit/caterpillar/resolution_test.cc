// The model's resolution (effect.lump_compliance_per_mpa): each lump built as two deformable
// half-lumps joined by the silicone block between their centres. The split model must keep
// the robot's geometry and mass, deform as a beam of modulus E = 1/compliance, stay rigid
// where the timestep cannot resolve the block, and change how the robot walks.
#include <cmath>
#include <vector>

#include "tests/unit/caterpillar/test_helpers.h"
#include "workers/models/caterpillar/caterpillar_eval.h"
#include "workers/models/caterpillar/gait.h"
#include "workers/models/caterpillar/param_overrides.h"

namespace gaitforge::caterpillar::testing {
namespace {

CaterpillarParams Split(double compliance_per_mpa) {
  CaterpillarParams p = Params();
  const absl::Status s = SetParam(p, "effect.lump_compliance_per_mpa", compliance_per_mpa);
  EXPECT_TRUE(s.ok()) << s;
  return p;
}

// The paper's silicone, 435 kPa.
constexpr double kPaperCompliance = 1 / 0.435;

// A hand-made gait (T = 0.7 s) that moves every actuator.
const std::vector<double> kGenes = {0.05, 0.35, 0.65, 0.5,  0.8, 0.1, 0.3,
                                    0.6,  0.9,  0.75, 0.05, 0.4, 0.7};

TEST(CaterpillarResolution, SplitKeepsGeometryMassAndMarkers) {
  CaterpillarSim rigid(Params());
  CaterpillarSim split(Split(kPaperCompliance));
  ASSERT_EQ(split.body().parts_per_lump(), 2);
  ASSERT_EQ(split.body().body_count(), 12);
  ASSERT_EQ(split.body().lump_count(), 6);
  double mass = 0;
  for (int i = 0; i < split.body().body_count(); ++i) {
    dMass m;
    dBodyGetMass(split.body().body(i), &m);
    mass += m.mass;
  }
  EXPECT_NEAR(mass, 6 * Params().lumps.mass_kg, 1e-12);
  for (int k = 0; k < 6; ++k) {
    EXPECT_NEAR(split.body().Position(k).x, rigid.body().Position(k).x, 1e-12) << "lump " << k + 1;
    EXPECT_NEAR(split.body().Marker(k).x, rigid.body().Marker(k).x, 1e-12) << "marker " << k + 1;
    EXPECT_NEAR(split.body().Marker(k).z, rigid.body().Marker(k).z, 1e-12) << "marker " << k + 1;
  }
  ASSERT_EQ(split.actuator_lengths().size(), rigid.actuator_lengths().size());
  for (size_t i = 0; i < rigid.actuator_lengths().size(); ++i) {
    EXPECT_NEAR(split.actuator_lengths()[i], rigid.actuator_lengths()[i], 1e-12) << "actuator " << i;
  }
  // At rest on the ground both stand still; each half stands on its own two edges.
  Simulate(split, 0.5, 0);
  EXPECT_EQ(split.ground_contacts(), 24);
  for (int k = 0; k < 6; ++k) {
    EXPECT_NEAR(split.body().Position(k).x, rigid.body().Position(k).x, 1e-5) << "lump " << k + 1;
  }
}

// Pulled apart by F at its two ends, every inner block carries F and stretches F / (E A / l),
// every link between lumps stretches F / k as in the rigid model.
TEST(CaterpillarResolution, InnerBlockStretchesAsABeamOfModulusE) {
  const double compliance = 10;  // 1/MPa: E = 100 kPa, soft enough to measure
  const CaterpillarParams p = Split(compliance);
  CaterpillarSim sim(p, FreeChain());
  ASSERT_EQ(sim.body().parts_per_lump(), 2);
  const double force = 0.5;
  const int last = sim.body().body_count() - 1;
  Simulate(sim, 3.0, 0, [&](CaterpillarSim& s) {
    dBodyAddForce(s.body().body(0), -force, 0, 0);
    dBodyAddForce(s.body().body(last), force, 0, 0);
  });
  const auto& L = p.lumps;
  const double l = L.size_x_m / 2;
  const double k_inner = 1e6 / compliance * L.size_y_m * L.size_z_m / l;
  for (int k = 0; k < 6; ++k) {
    const double rear = dBodyGetPosition(sim.body().body(2 * k))[0];
    const double front = dBodyGetPosition(sim.body().body(2 * k + 1))[0];
    const double expected = force / k_inner;
    EXPECT_NEAR(front - rear - l, expected, 0.01 * expected) << "lump " << k + 1;
  }
  for (int k = 0; k < 5; ++k) {
    const double expected = force / p.Link(k + 1).axial_n_per_m;
    EXPECT_NEAR(sim.body().LinkExtension(k), expected, 0.01 * expected) << "link " << k + 1;
  }
}

// A bending moment tau at the two ends bends every block by tau / (E I / l).
TEST(CaterpillarResolution, InnerBlockBendsAsABeamOfModulusE) {
  const double compliance = 10;
  const CaterpillarParams p = Split(compliance);
  CaterpillarSim sim(p, FreeChain(2, 3));
  const double moment = 0.002;
  Simulate(sim, 3.0, 0, [&](CaterpillarSim& s) {
    dBodyAddTorque(s.body().body(0), 0, -moment, 0);
    dBodyAddTorque(s.body().body(3), 0, moment, 0);
  });
  const auto& L = p.lumps;
  const double kappa = 1e6 / compliance * L.size_y_m * std::pow(L.size_z_m, 3) / 12 / (L.size_x_m / 2);
  auto pitch = [&](int i) {
    const dReal* r = dBodyGetRotation(sim.body().body(i));
    return std::atan2(-r[8], r[0]);
  };
  for (int k = 0; k < 2; ++k) {
    const double bend = pitch(2 * k + 1) - pitch(2 * k);
    EXPECT_NEAR(std::fabs(bend), moment / kappa, 0.01 * moment / kappa) << "lump " << k + 2;
  }
}

// A block stiffer than the timestep resolves (h omega > 2.5) stays one rigid lump: the model
// is then exactly the paper's. At 1 ms that is E above about 0.7 MPa; at 0.25 ms it splits.
TEST(CaterpillarResolution, StiffLumpsStayRigidUnlessTheTimestepResolvesThem) {
  const CaterpillarParams stiff = Split(1.0);  // E = 1 MPa
  CaterpillarSim at_1ms(stiff, {}, 1e-3);
  CaterpillarSim at_quarter(stiff, {}, 0.25e-3);
  EXPECT_EQ(at_1ms.body().parts_per_lump(), 1);
  EXPECT_EQ(at_quarter.body().parts_per_lump(), 2);

  EvalOptions o;
  o.settle_cycles = 1;
  o.measured_cycles = 2;
  const auto rigid = EvaluateGait(Params(), *Gait::FromGenes(kGenes), o);
  const auto same = EvaluateGait(stiff, *Gait::FromGenes(kGenes), o);
  ASSERT_TRUE(rigid.valid && same.valid);
  EXPECT_EQ(rigid.distance_per_cycle_m, same.distance_per_cycle_m);
}

// Deformable lumps at the paper's modulus walk differently: the stroke is partly taken up
// by the blocks. Judged on strokes, not travel (travel is chaotic in numerical changes).
// Also: the split model stays valid over the timesteps the gap finder's ensemble uses.
TEST(CaterpillarResolution, SoftLumpsTakeUpPartOfTheStroke) {
  EvalOptions o;
  o.settle_cycles = 1;
  o.measured_cycles = 3;
  for (double h : {0.5e-3, 0.75e-3, 1e-3, 1.25e-3}) {
    o.timestep_s = h;
    for (double c : {kPaperCompliance, 25.0}) {
      const auto e = EvaluateGait(Split(c), *Gait::FromGenes(kGenes), o);
      EXPECT_TRUE(e.valid) << "h " << h << ", compliance " << c << ": " << e.reason;
    }
  }
  // A free pair of lumps with one actuator pushing: the soft blocks compress, so the lump
  // centres move apart by less of the actuator's extension than with rigid lumps.
  auto centres_per_stroke = [](const CaterpillarParams& p) {
    BuildOptions pair = FreeChain(1, 2);
    pair.actuators = true;
    CaterpillarSim sim(p, pair);
    const double centres0 = sim.body().Position(1).x - sim.body().Position(0).x;
    const double length0 = sim.actuator_lengths()[0];
    Simulate(sim, 0.3, 1u);  // T1 ON
    const double stroke = sim.actuator_lengths()[0] - length0;
    EXPECT_GT(stroke, 1e-3);
    return (sim.body().Position(1).x - sim.body().Position(0).x - centres0) / stroke;
  };
  const double rigid = centres_per_stroke(Params());
  const double soft = centres_per_stroke(Split(25.0));
  EXPECT_LT(soft, 0.8 * rigid) << "rigid " << rigid << ", soft " << soft;
}

}  // namespace
}  // namespace gaitforge::caterpillar::testing
