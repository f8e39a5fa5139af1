#include "workers/models/caterpillar/calibration_objective.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "absl/strings/ascii.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "workers/models/caterpillar/calibration_error.h"
#include "workers/models/caterpillar/caterpillar_eval.h"
#include "workers/models/caterpillar/gait.h"
#include "workers/models/caterpillar/param_overrides.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::caterpillar {
namespace {

using calibration::Metric;
using calibration::Signals;

enum class Mode { kShape, kPointwise, kStats };

struct Settings {
  Mode mode = Mode::kShape;
  Metric metric = Metric::kRmse;
  bool channels_given = false;
  std::vector<std::string> channels;
  int settle_cycles = 2;
  int max_shift = 10;
  double timestep_s = 0;
  double z_weight = 1;
  double min_distance_m = 1e-3;
  std::vector<double> weights;  // per recording; empty: equal
};

// A compared channel: its column in the recording and the marker (0..5) and axis (x y z).
struct Channel {
  std::string name;
  int column = -1;
  int marker = 0;
  int axis = 0;
};

// What one recording gives.
struct Comparison {
  double error = 0;
  int shift = 0;
  double time_shift_s = 0;
  std::array<double, 3> offset_sum{};  // per axis, over the compared channels
  std::array<int, 3> offset_count{};
  bool has_distance = false;
  double real_distance = 0, sim_distance = 0;
  double simulated_s = 0;
};

// "m3.z" -> marker 2, axis 2.
bool ParseMarkerChannel(std::string_view name, int& marker, int& axis) {
  if (name.size() != 4 || name[0] != 'm' || name[2] != '.') return false;
  if (name[1] < '1' || name[1] > '6') return false;
  const size_t a = std::string_view("xyz").find(name[3]);
  if (a == std::string_view::npos) return false;
  marker = name[1] - '1';
  axis = static_cast<int>(a);
  return true;
}

// A param's value, its default when absent; false when outside [lo, hi] or not whole.
bool Param(const objectives::EvalInput& in, const char* name, double lo, double hi, double fallback,
           bool integer, double& value, std::string& error) {
  auto it = in.params.find(name);
  value = it == in.params.end() ? fallback : it->second;
  if (!(value >= lo && value <= hi) || (integer && value != std::floor(value))) {
    error = absl::StrCat("param ", name, " = ", value, " is outside [", lo, ", ", hi, "]",
                         integer ? " (a whole number)" : "");
    return false;
  }
  return true;
}

absl::StatusOr<Settings> ParseSettings(const objectives::EvalInput& in,
                                       const CaterpillarParams& base) {
  Settings s;
  std::string error;
  double settle, shift, timestep_ms, z_weight, min_distance;
  if (!Param(in, "settle_cycles", 0, 20, 2, true, settle, error) ||
      !Param(in, "max_shift_samples", 0, 1000, 10, true, shift, error) ||
      !Param(in, "timestep_ms", 0.05, 2, base.simulation.timestep_s * 1e3, false, timestep_ms,
             error) ||
      !Param(in, "z_weight", 0, 100, 1, false, z_weight, error) ||
      !Param(in, "min_distance_m", 1e-6, 1, 1e-3, false, min_distance, error)) {
    return absl::InvalidArgumentError(error);
  }
  for (const auto& [name, value] : in.params) {
    if (name != "settle_cycles" && name != "max_shift_samples" && name != "timestep_ms" &&
        name != "z_weight" && name != "min_distance_m") {
      return absl::InvalidArgumentError(absl::StrCat(
          "unknown param ", name,
          " (known: settle_cycles, max_shift_samples, timestep_ms, z_weight, min_distance_m)"));
    }
  }
  s.settle_cycles = static_cast<int>(settle);
  s.max_shift = static_cast<int>(shift);
  s.timestep_s = timestep_ms * 1e-3;
  s.z_weight = z_weight;
  s.min_distance_m = min_distance;
  for (const auto& [name, value] : in.options) {
    if (name == "error") {
      if (value == "shape") {
        s.mode = Mode::kShape;
      } else if (value == "pointwise") {
        s.mode = Mode::kPointwise;
      } else if (value == "stats") {
        s.mode = Mode::kStats;
      } else {
        return absl::InvalidArgumentError(
            absl::StrCat("option error = '", value, "' is not one of shape, pointwise, stats"));
      }
    } else if (name == "metric") {
      auto m = calibration::ParseMetric(value);
      if (!m.ok()) return absl::InvalidArgumentError(absl::StrCat("option ", m.status().message()));
      s.metric = *m;
    } else if (name == "channels") {
      s.channels_given = true;
      for (absl::string_view part : absl::StrSplit(value, ',')) {
        const std::string c(absl::StripAsciiWhitespace(part));
        if (c.empty()) continue;
        int marker, axis;
        if (!ParseMarkerChannel(c, marker, axis)) {
          return absl::InvalidArgumentError(absl::StrCat(
              "option channels: '", c, "' is not a caterpillar marker channel m1.x .. m6.z"));
        }
        s.channels.push_back(c);
      }
      if (s.channels.empty()) {
        return absl::InvalidArgumentError("option channels names no channel");
      }
    } else if (name == "weights") {
      double total = 0;
      for (absl::string_view part : absl::StrSplit(value, ',')) {
        double w = 0;
        if (!absl::SimpleAtod(absl::StripAsciiWhitespace(part), &w) || !std::isfinite(w) ||
            w < 0 || w > 1e6) {
          return absl::InvalidArgumentError(absl::StrCat(
              "option weights: '", part, "' is not a number in [0, 1e6] (one per recording)"));
        }
        s.weights.push_back(w);
        total += w;
      }
      if (!(total > 0)) return absl::InvalidArgumentError("option weights: all weights are 0");
    } else {
      return absl::InvalidArgumentError(
          absl::StrCat("unknown option ", name, " (known: error, metric, channels, weights)"));
    }
  }
  return s;
}

const std::vector<double>& SimSignal(const MarkerTrajectory& m, int marker, int axis) {
  return axis == 0 ? m.x[marker] : axis == 1 ? m.y[marker] : m.z[marker];
}

// Shape error of `channels` between the recording and the simulation, averaged over the
// cycles [kb, ke) (sim time origin 0, recording origin -offset).
calibration::ShiftedError ShapeError(const recording::Recording& rec, const MarkerTrajectory& sim,
                                     const std::vector<Channel>& channels, double period, int bins,
                                     double offset, int64_t kb, int64_t ke, int max_shift,
                                     Metric metric, double* real_rms = nullptr) {
  Signals real, simulated;
  for (const Channel& c : channels) {
    real.push_back(
        calibration::PeriodAverage(rec.t, rec.columns[c.column], period, bins, -offset, kb, ke));
    simulated.push_back(calibration::PeriodAverage(sim.t, SimSignal(sim, c.marker, c.axis), period,
                                                   bins, 0.0, kb, ke, max_shift));
  }
  if (real_rms) {
    double sum = 0;
    int64_t n = 0;
    for (const auto& r : real) {
      double mean = 0;
      for (double v : r) mean += v;
      mean /= static_cast<double>(r.size());
      for (double v : r) sum += (v - mean) * (v - mean);
      n += static_cast<int64_t>(r.size());
    }
    *real_rms = n ? std::sqrt(sum / static_cast<double>(n)) : 0;
  }
  return calibration::PaddedShiftInvariantError(metric, real, simulated, max_shift, true);
}

absl::StatusOr<Comparison> Compare(const CaterpillarParams& params, const recording::Recording& rec,
                                   double offset, const Settings& s) {
  Comparison out;
  if (!rec.meta.robot.empty() && rec.meta.robot != "caterpillar") {
    return absl::InvalidArgumentError(
        absl::StrCat("a recording of robot '", rec.meta.robot, "', not the caterpillar"));
  }
  const size_t n = rec.t.size();
  if (n < 2) return absl::InvalidArgumentError("fewer than 2 samples");
  if (rec.columns.size() != rec.channels.size()) {
    return absl::InvalidArgumentError("channel names and columns disagree");
  }
  for (const auto& col : rec.columns) {
    if (col.size() != n) return absl::InvalidArgumentError("a column's length differs from t's");
  }
  auto gait = Gait::FromGenes(rec.meta.genes);
  if (!gait.ok()) {
    return absl::InvalidArgumentError(absl::StrCat("meta.genes: ", gait.status().message()));
  }
  const double period = gait->period_s();
  const double dt = rec.dt > 0 ? rec.dt : (rec.t.back() - rec.t.front()) / (n - 1);
  if (!(dt > 0) || !std::isfinite(dt)) return absl::InvalidArgumentError("no sampling interval");

  // The compared channels, and every x channel (for the centroid).
  std::vector<Channel> channels, x_channels;
  for (size_t c = 0; c < rec.channels.size(); ++c) {
    Channel ch{rec.channels[c], static_cast<int>(c)};
    if (!ParseMarkerChannel(ch.name, ch.marker, ch.axis)) continue;
    if (ch.axis == 0) x_channels.push_back(ch);
    if (!s.channels_given) channels.push_back(ch);
  }
  for (const std::string& name : s.channels) {
    Channel ch{name, rec.ChannelIndex(name)};
    if (ch.column < 0) {
      return absl::InvalidArgumentError(absl::StrCat("no channel ", name, " (option channels)"));
    }
    ParseMarkerChannel(name, ch.marker, ch.axis);
    channels.push_back(ch);
  }
  if (channels.empty()) return absl::InvalidArgumentError("no marker channel m1.x .. m6.z");

  // The simulated run: from rest, to past the recording's end.
  const double settle_t = s.settle_cycles * period;
  const double last = rec.t.back() + offset;
  if (last <= settle_t) {
    return absl::InvalidArgumentError(absl::StrCat("the recording ends at simulated time ", last,
                                                   " s, within the ", s.settle_cycles,
                                                   " settle cycles of ", period, " s"));
  }
  const double horizon = last + (s.max_shift + 2) * dt + period;
  const double cycles = std::ceil(horizon / period);
  if (cycles > 1e6) return absl::InvalidArgumentError("the recording spans over 1e6 gait cycles");
  EvalOptions options;
  options.settle_cycles = 0;
  options.measured_cycles = static_cast<int>(cycles);
  options.timestep_s = s.timestep_s;
  // Markers at the recording's interval, or finer by a whole factor when it spans at least
  // two timesteps per sample (less interpolation error; the recorded times stay on the grid).
  const int oversample = std::max(1, static_cast<int>(std::floor(dt / (2 * s.timestep_s) + 1e-9)));
  options.marker_rate_hz = oversample / dt;
  const GaitEvaluation e = EvaluateGait(params, *gait, options);
  out.simulated_s = e.simulated_s;
  if (!e.valid) return absl::AbortedError(absl::StrCat("simulation: ", e.reason));
  const MarkerTrajectory& sim = e.markers;
  if (sim.t.size() < 2) return absl::InternalError("the simulation recorded no markers");

  // Whole gait cycles of the recording after the settle cycles.
  const int bins = calibration::BinsPerPeriod(period, dt);
  auto [kb, ke] = calibration::WholeCycles(rec.t.front(), rec.t.back(), period, bins, -offset);
  kb = std::max<int64_t>(kb, s.settle_cycles);
  const bool whole_cycles = kb < ke;

  // Distance per cycle of the centroid over the whole cycles, the simulation interpolated at
  // the recorded times moved by the best shift found (real[i] ~ sim[i + shift]).
  auto compute_distance = [&](double shift_s) {
    if (!whole_cycles || x_channels.empty()) return;
    std::vector<double> t, real_x, sim_x;
    const double lo = kb * period - 1e-9, hi = ke * period + 1e-9;
    for (size_t j = 0; j < n; ++j) {
      const double ts = rec.t[j] + offset;
      if (ts < lo || ts > hi) continue;
      double r = 0, m = 0;
      for (const Channel& c : x_channels) {
        r += rec.columns[c.column][j];
        m += calibration::Interpolate(sim.t, sim.x[c.marker], ts + shift_s);
      }
      t.push_back(ts);
      real_x.push_back(r / x_channels.size());
      sim_x.push_back(m / x_channels.size());
    }
    if (t.size() >= 2) {
      out.has_distance = true;
      out.real_distance = calibration::DistancePerCycle(t, real_x, period);
      out.sim_distance = calibration::DistancePerCycle(t, sim_x, period);
    }
  };

  auto add_offsets = [&](const std::vector<Channel>& chs, const std::vector<double>& offsets) {
    for (size_t c = 0; c < chs.size() && c < offsets.size(); ++c) {
      out.offset_sum[chs[c].axis] += offsets[c];
      ++out.offset_count[chs[c].axis];
    }
  };
  auto no_cycles = [&] {
    return absl::InvalidArgumentError(absl::StrCat("the recording [", rec.t.front(), ", ",
                                                   rec.t.back(), "] s (simulated time + ", offset,
                                                   " s) holds no whole gait cycle of ", period,
                                                   " s after ", s.settle_cycles, " settle cycles"));
  };

  if (s.mode == Mode::kShape) {
    if (!whole_cycles) return no_cycles();
    const int shift = std::min(s.max_shift, bins / 2);
    const auto best = ShapeError(rec, sim, channels, period, bins, offset, kb, ke, shift, s.metric);
    out.error = best.error;
    out.shift = best.shift;
    out.time_shift_s = best.shift * period / bins;
    add_offsets(channels, best.offsets);
  } else if (s.mode == Mode::kPointwise) {
    std::vector<double> times;
    Signals real(channels.size());
    const double lo = settle_t + s.max_shift * dt, hi = sim.t.back() - s.max_shift * dt;
    for (size_t j = 0; j < n; ++j) {
      const double ts = rec.t[j] + offset;
      if (ts < lo || ts > hi) continue;
      times.push_back(ts);
      for (size_t c = 0; c < channels.size(); ++c)
        real[c].push_back(rec.columns[channels[c].column][j]);
    }
    if (times.empty()) {
      return absl::InvalidArgumentError(absl::StrCat(
          "no recorded sample lies after the settle cycles (simulated time ", lo, " s)"));
    }
    const auto best =
        calibration::MinimumOverShifts(s.max_shift, [&](int shift, std::vector<double>* offsets) {
          Signals simulated(channels.size());
          for (size_t c = 0; c < channels.size(); ++c) {
            const std::vector<double>& x = SimSignal(sim, channels[c].marker, channels[c].axis);
            simulated[c].reserve(times.size());
            for (double ts : times)
              simulated[c].push_back(calibration::Interpolate(sim.t, x, ts + shift * dt));
          }
          return calibration::PooledError(s.metric, real, simulated, 0,
                                          static_cast<int64_t>(times.size()), 0, true, offsets);
        });
    out.error = best.error;
    out.shift = best.shift;
    out.time_shift_s = best.shift * dt;
    add_offsets(channels, best.offsets);
  } else {  // stats
    if (!whole_cycles) return no_cycles();
    std::vector<Channel> z;
    for (const Channel& c : channels) {
      if (c.axis == 2) z.push_back(c);
    }
    double z_term = 0;
    if (!z.empty() && s.z_weight > 0) {
      const int shift = std::min(s.max_shift, bins / 2);
      double rms = 0;
      const auto best =
          ShapeError(rec, sim, z, period, bins, offset, kb, ke, shift, s.metric, &rms);
      z_term = s.z_weight * best.error / std::max(rms, 1e-6);
      out.shift = best.shift;
      out.time_shift_s = best.shift * period / bins;
      add_offsets(z, best.offsets);
    }
    compute_distance(out.time_shift_s);
    if (!out.has_distance) {
      return absl::InvalidArgumentError("error = stats needs m*.x channels for the distance");
    }
    out.error = std::fabs(out.sim_distance - out.real_distance) /
                    std::max(std::fabs(out.real_distance), s.min_distance_m) +
                z_term;
    return out;
  }
  compute_distance(out.time_shift_s);
  return out;
}

}  // namespace

objectives::EvalResult CalibrationObjective::Evaluate(const objectives::EvalInput& in) const {
  sim::InitThread();  // once per thread; later calls are free
  objectives::EvalResult r;
  auto settings = ParseSettings(in, params_);
  if (!settings.ok()) {
    r.reason = std::string(settings.status().message());
    return r;
  }
  if (in.gene_names.size() != in.genes.size()) {
    r.reason =
        absl::StrCat("caterpillar.calibration needs a name for every gene: ", in.genes.size(),
                     " genes, ", in.gene_names.size(), " names");
    return r;
  }
  CaterpillarParams params = params_;
  double offset = 0;
  for (size_t i = 0; i < in.genes.size(); ++i) {
    const std::string& name = in.gene_names[i];
    if (name == kTimeOffsetParam) {
      if (!std::isfinite(in.genes[i])) {
        r.reason = absl::StrCat("gene ", i, " (", name, ") is not finite");
        return r;
      }
      offset = in.genes[i];
      continue;
    }
    if (absl::Status st = SetParam(params, name, in.genes[i]); !st.ok()) {
      r.reason = absl::StrCat("gene ", i, ": ", st.message());
      return r;
    }
  }
  // Without an explicit timestep_ms, the (possibly overridden) parameters' own timestep.
  if (!in.params.count("timestep_ms")) settings->timestep_s = params.simulation.timestep_s;
  if (in.recordings.empty()) {
    r.reason = "caterpillar.calibration needs at least one recording";
    return r;
  }
  if (!settings->weights.empty() && settings->weights.size() != in.recordings.size()) {
    r.reason = absl::StrCat("option weights: ", settings->weights.size(), " weights for ",
                            in.recordings.size(), " recordings (one per recording)");
    return r;
  }
  double sum = 0, weight_sum = 0, simulated = 0;
  std::array<double, 3> offset_sum{};
  std::array<int, 3> offset_count{};
  for (size_t i = 0; i < in.recordings.size(); ++i) {
    if (!in.recordings[i]) {
      r.reason = absl::StrCat("recording ", i, " is missing");
      return r;
    }
    auto c = Compare(params, *in.recordings[i], offset, *settings);
    if (!c.ok()) {
      r.reason = absl::StrCat("recording ", i, ": ", c.status().message());
      r.metrics["simulated_s"] = simulated;
      return r;
    }
    simulated += c->simulated_s;
    const double w = settings->weights.empty() ? 1.0 : settings->weights[i];
    sum += w * c->error;
    weight_sum += w;
    const std::string k = absl::StrCat(i);
    r.metrics["error_" + k] = c->error;
    r.metrics["best_shift_" + k] = c->shift;
    r.metrics["time_shift_s_" + k] = c->time_shift_s;
    if (c->has_distance) {
      r.metrics["sim_distance_per_cycle_" + k] = c->sim_distance;
      r.metrics["real_distance_per_cycle_" + k] = c->real_distance;
      if (std::fabs(c->sim_distance) > 1e-12) {
        r.metrics["distance_ratio_" + k] = c->real_distance / c->sim_distance;
      }
    }
    for (int a = 0; a < 3; ++a) {
      offset_sum[a] += c->offset_sum[a];
      offset_count[a] += c->offset_count[a];
    }
  }
  const char* axis_names[3] = {"offset_x", "offset_y", "offset_z"};
  for (int a = 0; a < 3; ++a) {
    if (offset_count[a] > 0) r.metrics[axis_names[a]] = offset_sum[a] / offset_count[a];
  }
  const double error = sum / weight_sum;
  r.metrics["error"] = error;
  r.metrics["simulated_s"] = simulated;
  r.valid = true;
  r.fitness = -error;
  return r;
}

void RegisterCaterpillarCalibration(objectives::ObjectiveRegistry& registry) {
  registry.Register(kCalibrationObjectiveName,
                    std::make_shared<CalibrationObjective>(DefaultCaterpillarParams()));
}

}  // namespace gaitforge::caterpillar
