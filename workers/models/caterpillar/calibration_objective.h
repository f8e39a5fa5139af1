#pragma once
// "caterpillar.calibration": how far the caterpillar model is from recordings of the robot
// (calibration after paper 003: CMA-ES over the uncertain parameters of the model, a
// phase-shift-invariant error between period-averaged signals). Fitness = -(mean error over
// the recordings); higher is better, 0 is a perfect match.
//
// Genes are model parameters by name (input.gene_names; param_overrides.h lists them, e.g.
// actuators.force_n, scale.link_stiffness), set in gene order on a copy of caterpillar.yaml,
// and nuisance parameters of the comparison:
//   nuisance.time_offset_s  recording time t corresponds to simulated time t + offset
//                           (both count from rest; default 0)
// There is no default space: a calibration study names its parameters in `bounds`.
//
// For each recording: the model runs the recording's gait (meta.genes) from rest, long
// enough to cover the recording's time span, markers sampled at the recording's interval dt
// divided by q = max(1, floor(dt / (2 timesteps))) (dt = 10 ms at 1 ms steps: every 2 ms),
// and interpolated linearly at the recorded times (+ time offset). Only what lies at
// simulated time >= settle_cycles periods takes part. Option `error`:
//   shape      (default) both signals are averaged over the recording's whole gait cycles into
//              one cycle of round(T / dt) bins (paper 003, Fig. 4a), each channel's constant
//              offset is profiled out and the error is the minimum over shifts of up to
//              max_shift_samples bins (paper 003, eq. 4; at most half a period). x channels
//              keep their mean drift per cycle as a ramp, so the shape also carries travel.
//   pointwise  sample by sample over the whole recording, offsets profiled, shifts of up to
//              max_shift_samples recording intervals. Hopping makes single trajectories
//              chaotic (../shared/robots/caterpillar.md): use it for synthetic checks only.
//   stats      |d_sim - d_real| / max(|d_real|, min_distance_m), d = distance per cycle of the
//              centroid (mean of the m*.x channels, least-squares slope over the whole cycles
//              times T), plus z_weight * the shape error of the selected z channels divided
//              by their RMS amplitude (dimensionless).
// Option `metric`: rmse (default) | mae (paper 003). Option `channels`: comma-separated
// channel names (default: every marker channel m1.x .. m6.z of the recording).
// Params (numeric; defaults): settle_cycles 0..20 (2), max_shift_samples 0..1000 (10),
// timestep_ms 0.05..2 (caterpillar.yaml), z_weight 0..100 (1), min_distance_m 1e-6..1 (1e-3).
//
// Metrics: error (the mean), error_<i> per recording, sim_distance_per_cycle_<i>,
// real_distance_per_cycle_<i> (m), distance_ratio_<i> (real / sim, paper 000 Fig. 9; absent
// when the simulation does not move), best_shift_<i> (samples or bins; real[i] matches
// sim[i + shift]), time_shift_s_<i> (the same in seconds), offset_x, offset_y, offset_z (mean
// profiled offset real - sim over the compared channels of that axis and the recordings, m),
// simulated_s. A diverging simulation, a bad gene name or value, a recording the model
// cannot compare with: valid = false with the reason.
// Thread-safe and deterministic: every call builds its own ODE worlds.
#include <memory>

#include "workers/models/caterpillar/caterpillar_eval.h"
#include "workers/models/caterpillar/caterpillar_params.h"
#include "workers/objectives/recording_comparison.h"
#include "workers/objectives/objective.h"

namespace gaitforge::caterpillar {

class CalibrationObjective : public objectives::Objective {
 public:
  explicit CalibrationObjective(CaterpillarParams params) : params_(std::move(params)) {}
  objectives::EvalResult Evaluate(const objectives::EvalInput& input) const override;

 private:
  const CaterpillarParams params_;
};

inline constexpr char kCalibrationObjectiveName[] = "caterpillar.calibration";

// The markers as recording channels m1.x, m1.y, m1.z, ..., m6.z.
calibration::Trajectory MarkerChannels(const MarkerTrajectory& m);

// Registers "caterpillar.calibration" with the installed caterpillar.yaml. Throws
// std::runtime_error when that file is missing or invalid.
void RegisterCaterpillarCalibration(objectives::ObjectiveRegistry& registry);

}  // namespace gaitforge::caterpillar
