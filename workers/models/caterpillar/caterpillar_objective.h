#pragma once
// "caterpillar.distance": the paper's fitness for the 13-gene caterpillar gait, metres of
// forward travel per gait cycle (higher is better). Genes are physical values, not mapped
// through the study's bounds: [a_T1..a_B3 (phase), d_T1..d_B3 (phase), T (s)].
// Params (validated by the coordinator against the catalog; re-checked here):
//   cycles         measured cycles, 1..50, default 1
//   settle_cycles  cycles from rest before measuring, 0..20, default 2
//   timestep_ms    0.05..2, default from caterpillar.yaml (1 ms)
//   start_phase    0..1 cycles, default 0: the gait's phase at t = 0
// Metrics: distance_per_cycle (m), max_body_pitch (rad), max_stroke (m), actuator_energy (J),
// airborne_fraction, simulated_s (s).
// Thread-safe: every call builds its own ODE world; results are bit-identical across threads
// and call orders.
#include <memory>

#include "workers/models/caterpillar/caterpillar_params.h"
#include "workers/objectives/objective.h"

namespace gaitforge::caterpillar {

class CaterpillarObjective : public objectives::Objective {
 public:
  explicit CaterpillarObjective(CaterpillarParams params) : params_(std::move(params)) {}
  objectives::EvalResult Evaluate(const objectives::EvalInput& input) const override;

 private:
  const CaterpillarParams params_;
};

inline constexpr char kCaterpillarObjectiveName[] = "caterpillar.distance";

// Registers "caterpillar.distance" with the installed caterpillar.yaml. Throws
// std::runtime_error when that file is missing or invalid.
void RegisterCaterpillar(objectives::ObjectiveRegistry& registry);

}  // namespace gaitforge::caterpillar
