#include "workers/models/caterpillar/caterpillar_eval.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "workers/models/caterpillar/caterpillar_sim.h"

namespace gaitforge::caterpillar {
namespace {

double MeanX(const CaterpillarBody& body) {
  double sum = 0;
  for (int k = 0; k < body.lump_count(); ++k) sum += body.Position(k).x;
  return sum / body.lump_count();
}

double BodyPitch(const CaterpillarBody& body) {
  const Vec3 rear = body.Position(0), front = body.Position(body.lump_count() - 1);
  return std::atan2(front.z - rear.z, front.x - rear.x);
}

}  // namespace

GaitEvaluation EvaluateGait(const CaterpillarParams& params, const Gait& gait,
                            const EvalOptions& options) {
  GaitEvaluation out;
  const int settle =
      options.settle_cycles >= 0 ? options.settle_cycles : params.simulation.settle_cycles;
  const int measured =
      options.measured_cycles >= 0 ? options.measured_cycles : params.simulation.measured_cycles;
  if (measured < 1) throw std::invalid_argument("EvaluateGait: measured_cycles must be >= 1");
  CaterpillarSim sim(params, BuildOptions{}, options.timestep_s);
  const double h = sim.timestep();
  const double T = gait.period_s();
  const double phase_s = options.start_phase * T;  // 0: the paper's start, bit for bit
  // Step counts from integer arithmetic: the measured window starts at exactly settle * T
  // up to one step (the step that contains it).
  const int64_t settle_steps = std::llround(settle * T / h);
  const int64_t total_steps = std::llround((settle + measured) * T / h);
  const double min_len = params.actuators.min_length_m;

  out.min_actuator_length_m = out.max_actuator_length_m = min_len;
  double start_x = MeanX(sim.body());
  int64_t airborne = 0;
  double next_sample = settle_steps * h;
  const double sample_dt = options.marker_rate_hz > 0 ? 1.0 / options.marker_rate_hz : 0;
  auto record_markers = [&] {
    out.markers.t.push_back(sim.time());
    for (int k = 0; k < 6; ++k) {
      const Vec3 m = sim.body().Marker(k);
      out.markers.x[k].push_back(m.x);
      out.markers.y[k].push_back(m.y);
      out.markers.z[k].push_back(m.z);
    }
  };

  for (int64_t n = 0; n < total_steps; ++n) {
    const bool measuring = n >= settle_steps;
    if (n == settle_steps) start_x = MeanX(sim.body());
    if (measuring && sample_dt > 0 && sim.time() >= next_sample - 0.5 * h) {
      record_markers();
      next_sample += sample_dt;
    }
    const sim::SimOutcome step = sim.Step(gait.OnMask(sim.time() + phase_s));
    if (!step.ok) {
      out.reason = step.reason;
      out.simulated_s = sim.time();
      return out;
    }
    for (double len : sim.actuator_lengths()) {
      out.min_actuator_length_m = std::min(out.min_actuator_length_m, len);
      out.max_actuator_length_m = std::max(out.max_actuator_length_m, len);
      if (measuring) out.max_stroke_m = std::max(out.max_stroke_m, len - min_len);
    }
    if (measuring) {
      out.actuator_energy_j += sim.last_actuator_work();
      if (sim.ground_contacts() == 0) ++airborne;
      out.max_body_pitch_rad = std::max(out.max_body_pitch_rad, std::fabs(BodyPitch(sim.body())));
    }
  }
  if (sample_dt > 0 && sim.time() >= next_sample - 0.5 * h) record_markers();
  if (total_steps == settle_steps) start_x = MeanX(sim.body());
  out.valid = true;
  out.distance_per_cycle_m = (MeanX(sim.body()) - start_x) / measured;
  out.airborne_fraction =
      static_cast<double>(airborne) / static_cast<double>(std::max<int64_t>(1, total_steps - settle_steps));
  out.simulated_s = sim.time();
  return out;
}

}  // namespace gaitforge::caterpillar
