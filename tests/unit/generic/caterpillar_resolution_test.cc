// The generic builder's resolution (effect.lump_compliance_per_mpa) on the caterpillar: each
// body that spring links join built as two deformable halves joined by the block of
// material between their centres. The split robot must keep its geometry and mass, deform
// as a beam of modulus E = 1/compliance, stay rigid where the timestep cannot resolve the
// block, and change how the robot walks.
#include <cmath>
#include <string>
#include <vector>

#include "tests/unit/generic/caterpillar_rig.h"
#include "workers/models/generic/generic_gait.h"

namespace gaitforge::generic::testing {
namespace {

constexpr char kCompliance[] = "effect.lump_compliance_per_mpa";
// The paper's silicone, 435 kPa.
constexpr double kPaperCompliance = 1 / 0.435;

// A hand-made gait (T = 0.7 s) that moves every piston.
const std::vector<double> kGenes = {0.05, 0.35, 0.65, 0.5,  0.8, 0.1, 0.3,
                                    0.6,  0.9,  0.75, 0.05, 0.4, 0.7};

const robots::RobotDescriptor& Caterpillar() { return robots::Robot("caterpillar"); }

ParamValues Split(double compliance_per_mpa) {
  ParamValues v(Caterpillar());
  const absl::Status s = v.Set(kCompliance, compliance_per_mpa);
  EXPECT_TRUE(s.ok()) << s;
  return v;
}

TEST(CaterpillarResolution, SplitKeepsGeometryMassAndMarkers) {
  Rig rigid = MakeRig();
  Rig split = MakeRig(Cut{}, {{kCompliance, kPaperCompliance}});
  ASSERT_EQ(split->parts(0), 2);
  ASSERT_EQ(split->ode_body_count(), 12);
  ASSERT_EQ(split->body_count(), 6);
  double mass = 0;
  for (int i = 0; i < split->ode_body_count(); ++i) {
    dMass m;
    dBodyGetMass(split->ode_body(i), &m);
    mass += m.mass;
  }
  EXPECT_NEAR(mass, 6 * rigid("lumps.mass_kg"), 1e-12);
  for (int k = 0; k < 6; ++k) {
    EXPECT_NEAR(split->BodyCentre(k)[0], rigid->BodyCentre(k)[0], 1e-12) << "lump " << k + 1;
    for (const char* axis : {".x", ".z"}) {
      const std::string m = "m" + std::to_string(k + 1) + axis;
      EXPECT_NEAR(*split->Channel(m), *rigid->Channel(m), 1e-12) << m;
    }
  }
  ASSERT_EQ(split->piston_extensions().size(), rigid->piston_extensions().size());
  for (size_t i = 0; i < rigid->piston_extensions().size(); ++i)
    EXPECT_NEAR(split->piston_extensions()[i], rigid->piston_extensions()[i], 1e-12) << "piston " << i;
  // At rest on the ground both stand still; each half stands on its own two edges.
  Simulate(split, 0.5, 0);
  EXPECT_EQ(split->ground_contacts(), 24);
  for (int k = 0; k < 6; ++k)
    EXPECT_NEAR(split->BodyCentre(k)[0], rigid->BodyCentre(k)[0], 1e-5) << "lump " << k + 1;
}

// Pulled apart by F at its two ends, every inner block carries F and stretches F / (E A / l),
// every link between lumps stretches F / k as in the rigid robot.
TEST(CaterpillarResolution, InnerBlockStretchesAsABeamOfModulusE) {
  const double compliance = 10;  // 1/MPa: E = 100 kPa, soft enough to measure
  Rig rig = MakeRig(FreeChain(), {{kCompliance, compliance}});
  ASSERT_EQ(rig->parts(0), 2);
  const double force = 0.5;
  const int last = rig->ode_body_count() - 1;
  Simulate(rig, 3.0, 0, [&](Rig& r) {
    dBodyAddForce(r->ode_body(0), -force, 0, 0);
    dBodyAddForce(r->ode_body(last), force, 0, 0);
  });
  const double l = rig("lumps.size_x_m") / 2;
  const double k_inner = 1e6 / compliance * rig("lumps.size_y_m") * rig("lumps.size_z_m") / l;
  for (int k = 0; k < 6; ++k) {
    const double rear = dBodyGetPosition(rig->ode_body(2 * k))[0];
    const double front = dBodyGetPosition(rig->ode_body(2 * k + 1))[0];
    const double expected = force / k_inner;
    EXPECT_NEAR(front - rear - l, expected, 0.01 * expected) << "lump " << k + 1;
  }
  for (int k = 0; k < 5; ++k) {
    const double expected = force / rig.Value(*rig.d->joints[k].axial_stiffness);
    EXPECT_NEAR(rig->LinkExtension(k), expected, 0.01 * expected) << "link " << k + 1;
  }
}

// A bending moment tau at the two ends bends every block by tau / (E I / l).
TEST(CaterpillarResolution, InnerBlockBendsAsABeamOfModulusE) {
  const double compliance = 10;
  Rig rig = MakeRig(FreeChain(2, 3), {{kCompliance, compliance}});
  const double moment = 0.002;
  Simulate(rig, 3.0, 0, [&](Rig& r) {
    dBodyAddTorque(r->ode_body(0), 0, -moment, 0);
    dBodyAddTorque(r->ode_body(3), 0, moment, 0);
  });
  const double kappa = 1e6 / compliance * rig("lumps.size_y_m") *
                       std::pow(rig("lumps.size_z_m"), 3) / 12 / (rig("lumps.size_x_m") / 2);
  for (int k = 0; k < 2; ++k) {
    const double bend = Pitch(rig->ode_body(2 * k + 1)) - Pitch(rig->ode_body(2 * k));
    EXPECT_NEAR(std::fabs(bend), moment / kappa, 0.01 * moment / kappa) << "lump " << k + 2;
  }
}

// A block stiffer than the timestep resolves (h omega > 2.5) stays one rigid lump: the robot
// is then exactly the paper's. At 1 ms that is E above about 0.7 MPa; at 0.25 ms it splits.
TEST(CaterpillarResolution, StiffLumpsStayRigidUnlessTheTimestepResolvesThem) {
  EXPECT_EQ(MakeRig(Cut{}, {{kCompliance, 1.0}}, 1e-3)->parts(0), 1);  // E = 1 MPa
  EXPECT_EQ(MakeRig(Cut{}, {{kCompliance, 1.0}}, 0.25e-3)->parts(0), 2);
  GaitOptions o;
  o.settle_cycles = 1;
  o.measured_cycles = 2;
  const GaitResult rigid = EvaluateGait(Caterpillar(), ParamValues(Caterpillar()), kGenes, o);
  const GaitResult same = EvaluateGait(Caterpillar(), Split(1.0), kGenes, o);
  ASSERT_TRUE(rigid.valid && same.valid);
  EXPECT_EQ(rigid.distance_per_cycle_m, same.distance_per_cycle_m);
}

// Deformable lumps at the paper's modulus walk differently: the stroke is partly taken up
// by the blocks. Judged on strokes, not travel (travel is chaotic in numerical changes).
// Also: the split robot stays valid over the timesteps the gap finder's ensemble uses.
TEST(CaterpillarResolution, SoftLumpsTakeUpPartOfTheStroke) {
  GaitOptions o;
  o.settle_cycles = 1;
  o.measured_cycles = 3;
  for (double h : {0.5e-3, 0.75e-3, 1e-3, 1.25e-3}) {
    o.timestep_s = h;
    for (double c : {kPaperCompliance, 25.0}) {
      const GaitResult e = EvaluateGait(Caterpillar(), Split(c), kGenes, o);
      EXPECT_TRUE(e.valid) << "h " << h << ", compliance " << c << ": " << e.reason;
    }
  }
  // A free pair of lumps with one piston pushing: the soft blocks compress, so the lump
  // centres move apart by less of the piston's extension than with rigid lumps.
  auto centres_per_stroke = [](double compliance) {
    Rig rig = MakeRig(Cut{1, 2, true, false, false}, {{kCompliance, compliance}});
    const double centres0 = rig->BodyCentre(1)[0] - rig->BodyCentre(0)[0];
    const double length0 = rig->piston_extensions()[0];
    Simulate(rig, 0.3, 1u);  // T1 ON
    const double stroke = rig->piston_extensions()[0] - length0;
    EXPECT_GT(stroke, 1e-3);
    return (rig->BodyCentre(1)[0] - rig->BodyCentre(0)[0] - centres0) / stroke;
  };
  const double rigid = centres_per_stroke(0), soft = centres_per_stroke(25.0);
  EXPECT_LT(soft, 0.8 * rigid) << "rigid " << rigid << ", soft " << soft;
}

}  // namespace
}  // namespace gaitforge::generic::testing
