#pragma once
// One evaluation of a gait (../shared/robots/caterpillar.md, "Fitness"): from rest, run
// settle_cycles gait cycles, then measured_cycles more; fitness is the forward (+x) travel of
// the mean of the lump centres over the measured cycles, per cycle (m).
#include <array>
#include <string>
#include <vector>

#include "workers/models/caterpillar/caterpillar_params.h"
#include "workers/models/caterpillar/gait.h"

namespace gaitforge::caterpillar {

struct EvalOptions {
  int settle_cycles = -1;      // < 0: params.simulation.settle_cycles
  int measured_cycles = -1;    // < 0: params.simulation.measured_cycles
  double timestep_s = 0;       // <= 0: params.simulation.timestep_s
  // The gait's phase at t = 0 (cycles, 0..1): the actuators follow OnMask(t + phase T).
  double start_phase = 0;
  // > 0: record the markers at this rate (Hz) over the measured cycles.
  double marker_rate_hz = 0;
};

// Markers m1..m6 in the world frame (m) at times t (s, from the start of the run).
struct MarkerTrajectory {
  std::vector<double> t;
  std::array<std::vector<double>, 6> x, y, z;
};

struct GaitEvaluation {
  bool valid = false;
  std::string reason;                // why not valid
  double distance_per_cycle_m = 0;   // the fitness
  double max_body_pitch_rad = 0;     // max |angle of the line from lump 1 to lump 6 centres|
  double max_stroke_m = 0;           // max actuator extension beyond min length
  double min_actuator_length_m = 0, max_actuator_length_m = 0;  // over the whole run
  double actuator_energy_j = 0;      // work of the ON actuator forces, measured cycles
  double airborne_fraction = 0;      // share of measured steps with no ground contact
  double simulated_s = 0;            // settle + measured time
  MarkerTrajectory markers;          // empty unless marker_rate_hz > 0
};

// Never throws for a diverging model: that is valid = false with the reason.
GaitEvaluation EvaluateGait(const CaterpillarParams& params, const Gait& gait,
                            const EvalOptions& options = {});

}  // namespace gaitforge::caterpillar
