#pragma once
// One-shot simulations of the caterpillar for reports and exports (gaitforge-sim): the
// same model and build as the workers, run on this machine, no coordinator involved.
#include <map>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "workers/models/caterpillar/caterpillar_eval.h"
#include "workers/models/caterpillar/caterpillar_params.h"
#include "workers/objectives/recording_comparison.h"

namespace gaitforge::simtool {

// Writes channels as a recording CSV (docs/recording-format.md: t, then the channels) and its
// JSON sidecar (robot, parameter file, the gait command, overrides).
absl::Status WriteChannels(const calibration::Trajectory& tr, const std::string& csv_path,
                           const std::string& robot, const std::string& params_path,
                           const std::vector<double>& genes, const std::string& note,
                           const std::vector<std::pair<std::string, double>>& overrides = {});

// `s` escaped for a JSON string.
std::string JsonEscape(const std::string& s);

// Writes markers as a recording CSV (docs/recording-format.md: t, m1.x .. m6.z in metres)
// and its JSON sidecar (robot, parameter file, command).
absl::Status WriteRecording(const caterpillar::MarkerTrajectory& m, const std::string& csv_path,
                            const std::string& params_path, const std::vector<double>& genes,
                            const std::string& note,
                            const std::vector<std::pair<std::string, double>>& overrides = {});

struct SweepPoint {
  double scale = 0;    // period multiplier (period sweep) or 0 (wave)
  double period_s = 0;
  std::string shape;   // wave: WaveShape::Name(); else empty
  caterpillar::GaitEvaluation eval;
};

// Evaluates `genes` with the period multiplied by each scale (same phase pattern).
std::vector<SweepPoint> PeriodSweep(const caterpillar::CaterpillarParams& params,
                                    const std::vector<double>& genes,
                                    const std::vector<double>& scales,
                                    const caterpillar::EvalOptions& options, int threads);

// The travelling-wave baseline at each period.
std::vector<SweepPoint> WaveSweep(const caterpillar::CaterpillarParams& params,
                                  const std::vector<double>& periods,
                                  const caterpillar::EvalOptions& options, int threads);

std::string SweepJson(const std::vector<SweepPoint>& points);

// "name=value,name=value" in order.
absl::StatusOr<std::vector<std::pair<std::string, double>>> ParseOverrides(const std::string& text);

// For each recording (comma-separated CSV paths with sidecars): the calibration objective's
// error and metrics with `overrides` as genes, and (with out_dir) the simulated markers of
// the recording's gait as out_dir/sim-<i>.csv. Returns JSON.
absl::StatusOr<std::string> CalibrationEval(
    const caterpillar::CaterpillarParams& params,
    const std::vector<std::pair<std::string, double>>& overrides, const std::string& recordings,
    const std::map<std::string, std::string>& options,
    const std::map<std::string, double>& objective_params, const std::string& out_dir,
    double rate);

// "k=v;k=v" (values may hold commas, e.g. channels=m1.x,m1.z).
absl::StatusOr<std::map<std::string, std::string>> ParseOptions(const std::string& text);

// "a,b,n": n values evenly spaced from a to b (geometric when `geometric`).
absl::StatusOr<std::vector<double>> ParseRange(const std::string& text, bool geometric);
// `count` numbers (the caterpillar's 13 by default), comma or space separated.
absl::StatusOr<std::vector<double>> ParseGenes(const std::string& text, size_t count = 13);

}  // namespace gaitforge::simtool
