#pragma once
// Shared set-up for the caterpillar model tests.
#include <cstdint>
#include <functional>

#include "gtest/gtest.h"
#include "workers/models/caterpillar/caterpillar_params.h"
#include "workers/models/caterpillar/caterpillar_sim.h"

namespace gaitforge::caterpillar::testing {

inline const CaterpillarParams& Params() { return DefaultCaterpillarParams(); }

// The robot with nothing but the links: no gravity, ground or actuators.
inline BuildOptions FreeChain(int first = 1, int last = 6) {
  BuildOptions o;
  o.first_lump = first;
  o.last_lump = last;
  o.gravity = false;
  o.ground = false;
  o.actuators = false;
  return o;
}

// Steps `seconds` with actuators `mask`; `before` runs before each step (to add loads) and
// `after` after it. Fails the test (and stops) if the model diverges.
inline void Simulate(CaterpillarSim& sim, double seconds, uint32_t mask,
                const std::function<void(CaterpillarSim&)>& before = nullptr,
                const std::function<void(CaterpillarSim&)>& after = nullptr) {
  const int64_t steps = static_cast<int64_t>(seconds / sim.timestep() + 0.5);
  for (int64_t i = 0; i < steps; ++i) {
    if (before) before(sim);
    const sim::SimOutcome o = sim.Step(mask);
    ASSERT_TRUE(o.ok) << o.reason;
    if (after) after(sim);
  }
}

inline double MeanX(const CaterpillarBody& b) {
  double s = 0;
  for (int k = 0; k < b.lump_count(); ++k) s += b.Position(k).x;
  return s / b.lump_count();
}

}  // namespace gaitforge::caterpillar::testing
