// Static deflection of the links: under an axial load F each link stretches F/k, under a
// bending moment tau each bends tau/kappa (paper's FEA stiffnesses). The spring is the stop
// row f = -k x_n - c v_{n+1}, exact at rest, so the tolerance is 0.5% (the remainder is the
// unfinished decay of the chain's slow, overdamped bending mode: 0.75% left after 1 s,
// 0.005% after 2 s; the tests run 3 s).
#include <cmath>

#include "tests/unit/caterpillar/test_helpers.h"

namespace gaitforge::caterpillar::testing {
namespace {

constexpr double kRelTol = 0.005;

TEST(CaterpillarStatics, AxialDeflectionIsLoadOverStiffness) {
  const CaterpillarParams& p = Params();
  CaterpillarSim sim(p, FreeChain());
  const double force = 0.1;  // N, the paper's FEA axial load
  Simulate(sim, 3.0, 0, [&](CaterpillarSim& s) {
    dBodyAddForce(s.body().lump(0), -force, 0, 0);
    dBodyAddForce(s.body().lump(5), force, 0, 0);
  });
  for (int k = 0; k < 5; ++k) {
    const double stretch = sim.body().Position(k + 1).x - sim.body().Position(k).x - p.lumps.spacing_m;
    const double expected = force / p.Link(k + 1).axial_n_per_m;
    EXPECT_NEAR(stretch, expected, kRelTol * expected) << "link " << k + 1;
    EXPECT_NEAR(sim.body().LinkExtension(k), expected, kRelTol * expected) << "link " << k + 1;
  }
}

TEST(CaterpillarStatics, BendingDeflectionIsMomentOverStiffness) {
  const CaterpillarParams& p = Params();
  CaterpillarSim sim(p, FreeChain());
  const double moment = 0.005;  // N m about +y: a pure moment through the whole chain
  Simulate(sim, 3.0, 0, [&](CaterpillarSim& s) {
    dBodyAddTorque(s.body().lump(0), 0, -moment, 0);
    dBodyAddTorque(s.body().lump(5), 0, moment, 0);
  });
  for (int k = 0; k < 5; ++k) {
    const double bend = sim.body().Pitch(k + 1) - sim.body().Pitch(k);
    const double expected = moment / p.Link(k + 1).bending_nm_per_rad;
    EXPECT_NEAR(bend, expected, kRelTol * expected) << "link " << k + 1;
    // No axial load: the links keep their length.
    EXPECT_NEAR(sim.body().LinkExtension(k), 0, 1e-6) << "link " << k + 1;
  }
}

}  // namespace
}  // namespace gaitforge::caterpillar::testing
