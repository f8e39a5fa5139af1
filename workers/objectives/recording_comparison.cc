// Comparing a model with recordings (recording_comparison.h).
#include "workers/objectives/recording_comparison.h"

#include <algorithm>
#include <cmath>
#include <functional>

#include "absl/strings/ascii.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "workers/objectives/acceleration_error.h"

namespace gaitforge::calibration {
namespace {

absl::Status ParseParams(const objectives::EvalInput& in, int default_settle, CompareSettings& s) {
  std::string error;
  double settle, shift, timestep_ms, z_weight, min_distance, window;
  if (!objectives::ParamInRange(in, "settle_cycles", 0, 20, default_settle, true, settle, error) ||
      !objectives::ParamInRange(in, "max_shift_samples", 0, 1000, 10, true, shift, error) ||
      !objectives::ParamInRange(in, "timestep_ms", 0.05, 2, 1, false, timestep_ms, error) ||
      !objectives::ParamInRange(in, "z_weight", 0, 100, 1, false, z_weight, error) ||
      !objectives::ParamInRange(in, "min_distance_m", 1e-6, 1, 1e-3, false, min_distance, error) ||
      !objectives::ParamInRange(in, "window_s", 0, 1e4, 0, false, window, error)) {
    return absl::InvalidArgumentError(error);
  }
  for (const auto& [name, value] : in.params) {
    if (name != "settle_cycles" && name != "max_shift_samples" && name != "timestep_ms" &&
        name != "z_weight" && name != "min_distance_m" && name != "window_s") {
      return absl::InvalidArgumentError(
          absl::StrCat("unknown param ", name,
                       " (known: settle_cycles, max_shift_samples, timestep_ms, z_weight, "
                       "min_distance_m, window_s)"));
    }
  }
  s.settle_cycles = static_cast<int>(settle);
  s.max_shift = static_cast<int>(shift);
  s.timestep_s = in.params.count("timestep_ms") ? timestep_ms * 1e-3 : 0;
  s.z_weight = z_weight;
  s.min_distance_m = min_distance;
  s.window_s = window;
  return absl::OkStatus();
}

absl::Status ParseWeights(const std::string& value, CompareSettings& s) {
  double total = 0;
  for (absl::string_view part : absl::StrSplit(value, ',')) {
    double w = 0;
    if (!absl::SimpleAtod(absl::StripAsciiWhitespace(part), &w) || !std::isfinite(w) || w < 0 ||
        w > 1e6) {
      return absl::InvalidArgumentError(absl::StrCat(
          "option weights: '", part, "' is not a number in [0, 1e6] (one per recording)"));
    }
    s.weights.push_back(w);
    total += w;
  }
  if (!(total > 0)) return absl::InvalidArgumentError("option weights: all weights are 0");
  return absl::OkStatus();
}

absl::Status ParseChannels(const std::string& value, const std::vector<std::string>& known,
                           const std::string& robot, CompareSettings& s) {
  for (absl::string_view part : absl::StrSplit(value, ',')) {
    const std::string c(absl::StripAsciiWhitespace(part));
    if (c.empty()) continue;
    if (std::find(known.begin(), known.end(), c) == known.end())
      return absl::InvalidArgumentError(absl::StrCat("option channels: '", c,
                                                     "' is not a channel of ", robot, " (",
                                                     absl::StrJoin(known, ", "), ")"));
    s.channels.push_back(c);
  }
  if (s.channels.empty()) return absl::InvalidArgumentError("option channels names no channel");
  return absl::OkStatus();
}

// 0, 1, 2 for a channel ending in .x, .y, .z (a position); -1 for another.
int AxisOf(std::string_view channel) {
  if (channel.size() < 3 || channel[channel.size() - 2] != '.') return -1;
  const size_t a = std::string_view("xyz").find(channel.back());
  return a == std::string_view::npos ? -1 : static_cast<int>(a);
}

// A compared channel: its column in the recording and in the simulation.
struct Channel {
  std::string name;
  int column = -1, sim = -1, axis = -1;
};

absl::StatusOr<std::vector<Channel>> ChosenChannels(const recording::Recording& rec,
                                                    const Trajectory& sim,
                                                    const CompareSettings& s) {
  std::vector<Channel> out;
  if (s.channels.empty()) {
    for (size_t c = 0; c < rec.channels.size(); ++c) {
      const int k = sim.Index(rec.channels[c]);
      if (k >= 0) out.push_back({rec.channels[c], static_cast<int>(c), k, AxisOf(rec.channels[c])});
    }
    if (out.empty())
      return absl::InvalidArgumentError(absl::StrCat(
          "no channel of the recording is one the model gives (", absl::StrJoin(sim.channels, ", "),
          ")"));
    return out;
  }
  for (const std::string& name : s.channels) {
    Channel ch{name, rec.ChannelIndex(name), sim.Index(name), AxisOf(name)};
    if (ch.column < 0)
      return absl::InvalidArgumentError(absl::StrCat("no channel ", name, " (option channels)"));
    if (ch.sim < 0)
      return absl::InvalidArgumentError(absl::StrCat("the model gives no channel ", name));
    out.push_back(ch);
  }
  return out;
}

// The best shift on the grid of `step` (a bin, a sample), refined to a fraction of it: the
// minimum of error_at(fine) for fine within half a step either side of 0 (golden section;
// error_at(0) is `grid`, the grid's best). A clock offset between a recording and the model
// is rarely a whole number of steps, and a fast signal (a servo's step) misaligned by half a
// step reads as an error many times the noise: without this a fit would have to find the
// offset to a fraction of a step (docs/calibration.md, "Alignment"). `fine` gets the shift's
// part off the grid, in seconds.
ShiftedError RefinedShift(double step, const ShiftedError& grid,
                          const std::function<ShiftedError(double fine)>& error_at,
                          double* fine) {
  *fine = 0;
  if (!(step > 0)) return grid;
  constexpr double kGolden = 0.6180339887498949;
  constexpr int kIterations = 12;  // the half step shrinks to 0.3% of a step
  double a = -0.5 * step, b = 0.5 * step;
  double x1 = b - kGolden * (b - a), x2 = a + kGolden * (b - a);
  ShiftedError f1 = error_at(x1), f2 = error_at(x2);
  for (int i = 0; i < kIterations; ++i) {
    if (f1.error <= f2.error) {
      b = x2, x2 = x1, f2 = f1, x1 = b - kGolden * (b - a), f1 = error_at(x1);
    } else {
      a = x1, x1 = x2, f1 = f2, x2 = a + kGolden * (b - a), f2 = error_at(x2);
    }
  }
  const bool first = f1.error <= f2.error;
  const ShiftedError& best = first ? f1 : f2;
  if (!(best.error < grid.error)) return grid;
  *fine = first ? x1 : x2;
  return best;
}

// Shape error of `channels` between the recording and the simulation, averaged over the
// cycles [kb, ke) from recording time `origin` (simulated time origin + offset), at the best
// shift: whole bins, then a fraction of one (RefinedShift; `fine_s`, seconds) unless
// max_shift is 0 (the recording's clock is the model's).
ShiftedError ShapeError(const recording::Recording& rec, const Trajectory& sim,
                        const std::vector<Channel>& channels, double period, int bins,
                        double origin, double offset, int64_t kb, int64_t ke, int max_shift,
                        Metric metric, double* real_rms = nullptr, double* fine_s = nullptr) {
  Signals real;
  for (const Channel& c : channels)
    real.push_back(PeriodAverage(rec.t, rec.columns[c.column], period, bins, origin, kb, ke));
  const auto at = [&](double fine) {
    Signals simulated;
    for (const Channel& c : channels)
      simulated.push_back(PeriodAverage(sim.t, sim.columns[c.sim], period, bins,
                                        origin + offset + fine, kb, ke, max_shift));
    return PaddedShiftInvariantError(metric, real, simulated, max_shift, true);
  };
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
  double fine = 0;
  const ShiftedError grid = at(0);
  const ShiftedError best = max_shift > 0 ? RefinedShift(period / bins, grid, at, &fine) : grid;
  if (fine_s) *fine_s = fine;
  return best;
}

// What CompareRecording's stages share.
struct Context {
  const recording::Recording& rec;
  const Trajectory& sim;
  const CompareSettings& s;
  std::vector<Channel> channels, x_channels;
  double period, offset, dt, settle_t;
  int bins;
  double origin;  // recording time where cycle 0 starts (RecordedCycles)
  int64_t kb, ke;
  Comparison out;

  void AddOffsets(const std::vector<Channel>& chs, const std::vector<double>& offsets) {
    for (size_t c = 0; c < chs.size() && c < offsets.size(); ++c) {
      if (chs[c].axis < 0) continue;
      out.offset_sum[chs[c].axis] += offsets[c];
      ++out.offset_count[chs[c].axis];
    }
  }
  absl::Status NoCycles() const {
    return absl::InvalidArgumentError(absl::StrCat(
        "the recording [", rec.t.front(), ", ", rec.t.back(), "] s (simulated time + ", offset,
        " s) holds no whole gait cycle of ", period, " s after ", s.settle_cycles,
        " settle cycles"));
  }
};

// Distance per cycle of the mean of the x channels over the whole cycles, the simulation
// interpolated at the recorded times moved by the best shift (real[i] ~ sim[i + shift]).
void Distance(Context& c, double shift_s) {
  if (c.kb >= c.ke || c.x_channels.empty()) return;
  std::vector<double> t, real_x, sim_x;
  const double lo = c.origin + c.kb * c.period - 1e-9, hi = c.origin + c.ke * c.period + 1e-9;
  for (size_t j = 0; j < c.rec.t.size(); ++j) {
    if (c.rec.t[j] < lo || c.rec.t[j] > hi) continue;
    const double ts = c.rec.t[j] + c.offset;
    double r = 0, m = 0;
    for (const Channel& ch : c.x_channels) {
      r += c.rec.columns[ch.column][j];
      m += Interpolate(c.sim.t, c.sim.columns[ch.sim], ts + shift_s);
    }
    t.push_back(ts);
    real_x.push_back(r / c.x_channels.size());
    sim_x.push_back(m / c.x_channels.size());
  }
  if (t.size() >= 2) {
    c.out.has_distance = true;
    c.out.real_distance = DistancePerCycle(t, real_x, c.period);
    c.out.sim_distance = DistancePerCycle(t, sim_x, c.period);
  }
}

absl::Status Pointwise(Context& c) {
  std::vector<double> times;
  Signals real(c.channels.size());
  // Which samples are compared depends on the recording alone, never on the fitted offset.
  const double lo = c.settle_t + c.s.max_shift * c.dt, hi = c.sim.t.back() - c.s.max_shift * c.dt;
  for (size_t j = 0; j < c.rec.t.size(); ++j) {
    const double ts = c.rec.t[j] + c.offset;
    if (c.rec.t[j] < lo || ts > hi) continue;
    times.push_back(ts);
    for (size_t k = 0; k < c.channels.size(); ++k)
      real[k].push_back(c.rec.columns[c.channels[k].column][j]);
  }
  if (times.empty())
    return absl::InvalidArgumentError(absl::StrCat(
        "no recorded sample lies after the settle cycles (simulated time ", lo, " s)"));
  const auto error_at = [&](double shift_s, std::vector<double>* offsets) {
    Signals simulated(c.channels.size());
    for (size_t k = 0; k < c.channels.size(); ++k) {
      const std::vector<double>& x = c.sim.columns[c.channels[k].sim];
      simulated[k].reserve(times.size());
      for (double ts : times) simulated[k].push_back(Interpolate(c.sim.t, x, ts + shift_s));
    }
    return PooledError(c.s.metric, real, simulated, 0, static_cast<int64_t>(times.size()), 0,
                       true, offsets);
  };
  const ShiftedError grid = MinimumOverShifts(
      c.s.max_shift, [&](int shift, std::vector<double>* offsets) {
        return error_at(shift * c.dt, offsets);
      });
  // The fraction of a sample about the grid's best shift (the whole search again would
  // cost 2 S + 1 times as much for the same continuum).
  const auto refined = [&](double fine) {
    ShiftedError e;
    e.shift = grid.shift;
    e.error = error_at(grid.shift * c.dt + fine, &e.offsets);
    return e;
  };
  double fine = 0;
  const ShiftedError best = c.s.max_shift > 0 ? RefinedShift(c.dt, grid, refined, &fine) : grid;
  c.out.error = best.error;
  c.out.shift = best.shift;
  c.out.time_shift_s = best.shift * c.dt + fine;
  c.AddOffsets(c.channels, best.offsets);
  return absl::OkStatus();
}

absl::Status Stats(Context& c) {
  if (c.kb >= c.ke) return c.NoCycles();
  std::vector<Channel> z;
  for (const Channel& ch : c.channels)
    if (ch.axis == 2) z.push_back(ch);
  double z_term = 0;
  if (!z.empty() && c.s.z_weight > 0) {
    const int shift = std::min(c.s.max_shift, c.bins / 2);
    double rms = 0;
    double fine = 0;
    const auto best = ShapeError(c.rec, c.sim, z, c.period, c.bins, c.origin, c.offset, c.kb, c.ke,
                                 shift, c.s.metric, &rms, &fine);
    z_term = c.s.z_weight * best.error / std::max(rms, 1e-6);
    c.out.shift = best.shift;
    c.out.time_shift_s = best.shift * c.period / c.bins + fine;
    c.AddOffsets(z, best.offsets);
  }
  Distance(c, c.out.time_shift_s);
  if (!c.out.has_distance)
    return absl::InvalidArgumentError("error = stats needs position .x channels for the distance");
  c.out.error = std::fabs(c.out.sim_distance - c.out.real_distance) /
                    std::max(std::fabs(c.out.real_distance), c.s.min_distance_m) +
                z_term;
  return absl::OkStatus();
}

// The compared channels as points: channels "<name>.x/.y/.z" of one name make one point's
// vector, any other channel is a point of its own.
std::vector<std::vector<Channel>> Points(const std::vector<Channel>& channels) {
  std::vector<std::vector<Channel>> points;
  std::vector<std::string> names;
  for (const Channel& ch : channels) {
    const std::string name = ch.axis >= 0 ? ch.name.substr(0, ch.name.size() - 2) : ch.name;
    const auto at = std::find(names.begin(), names.end(), name);
    if (ch.axis >= 0 && at != names.end()) {
      points[at - names.begin()].push_back(ch);
    } else {
      names.push_back(ch.axis >= 0 ? name : "");  // a non-position channel joins no other
      points.push_back({ch});
    }
  }
  return points;
}

// error = acceleration (CompareRecording): both sides on the recording's regular grid
// t_k = t_0 + k dt, through the same Savitzky-Golay filter.
absl::Status Accelerations(Context& c) {
  const double t0 = c.rec.t.front();
  const int64_t n = std::llround((c.rec.t.back() - t0) / c.dt) + 1;
  int64_t end = n - kSavitzkyGolayHalfWindow;
  if (c.s.window_s > 0) end = std::min<int64_t>(end, std::llround(c.s.window_s / c.dt) + 1);
  // A gait's settle cycles are left out as in the other modes (settle_t is 0 for a playback).
  const int64_t begin = std::max<int64_t>(
      kSavitzkyGolayHalfWindow, static_cast<int64_t>(std::ceil((c.settle_t - t0) / c.dt - 1e-9)));
  if (end - begin < 1)
    return absl::InvalidArgumentError(absl::StrCat(
        "error = acceleration compares samples with ", kSavitzkyGolayHalfWindow,
        " recorded samples on either side (the filter's window), and ",
        c.s.window_s > 0 ? absl::StrCat("window_s = ", c.s.window_s, " s") : "the recording",
        " at ", c.dt, " s intervals holds none: at least ", (kSavitzkyGolayHalfWindow + 1) * c.dt,
        " s of a recording of at least ", 2 * kSavitzkyGolayHalfWindow + 1, " samples"));
  const auto points = Points(c.channels);
  const auto accelerations = [&](bool simulated, double shift_s) {
    std::vector<Vectors> out;
    std::vector<double> x(n);
    for (const auto& point : points) {
      Vectors v;
      for (const Channel& ch : point) {
        for (int64_t k = 0; k < n; ++k) {
          const double t = t0 + static_cast<double>(k) * c.dt;
          x[k] = simulated ? Interpolate(c.sim.t, c.sim.columns[ch.sim], t + c.offset + shift_s)
                           : Interpolate(c.rec.t, c.rec.columns[ch.column], t);
        }
        v.push_back(SavitzkyGolaySecondDerivative(x, c.dt));
      }
      out.push_back(std::move(v));
    }
    return out;
  };
  const std::vector<Vectors> real = accelerations(false, 0);
  double best = -1;
  for (int shift = -c.s.max_shift; shift <= c.s.max_shift; ++shift) {
    const double e = RelativeAccelerationError(c.s.metric, real, accelerations(true, shift * c.dt),
                                               begin, end);
    if (e < 0)
      return absl::InvalidArgumentError(
          "error = acceleration: the recorded accelerations are all zero in the window");
    if (best < 0 || e < best || (e == best && std::abs(shift) < std::abs(c.out.shift))) {
      best = e;
      c.out.shift = shift;
    }
  }
  c.out.error = best;
  c.out.time_shift_s = c.out.shift * c.dt;
  return absl::OkStatus();
}

// The recording's whole gait cycles, counted from its first sample (cycle k starts at
// recording time t_first + k period), from the first that starts after `settle` periods.
// They depend on the recording alone: were they placed by the fitted time offset, a fit
// could win an extra cycle and with it the noise that averaging one more cycle removes
// (a 59 ms command delay "found" on a noisy null did exactly that).
std::pair<int64_t, int64_t> RecordedCycles(const recording::Recording& rec, double period, int bins,
                                           int settle) {
  const double t0 = rec.t.front();
  const auto [kb, ke] = WholeCycles(t0, rec.t.back(), period, bins, t0);
  const double tol = 1e-6 / bins;  // in cycles, as WholeCycles
  const auto first = static_cast<int64_t>(std::ceil(settle - t0 / period - tol));
  return {std::max(kb, first), ke};
}

absl::Status CheckShape(const recording::Recording& rec) {
  if (rec.t.size() < 2) return absl::InvalidArgumentError("fewer than 2 samples");
  if (rec.columns.size() != rec.channels.size())
    return absl::InvalidArgumentError("channel names and columns disagree");
  for (const auto& col : rec.columns)
    if (col.size() != rec.t.size())
      return absl::InvalidArgumentError("a column's length differs from t's");
  return absl::OkStatus();
}

}  // namespace

int Trajectory::Index(std::string_view name) const {
  for (size_t i = 0; i < channels.size(); ++i)
    if (channels[i] == name) return static_cast<int>(i);
  return -1;
}

absl::StatusOr<CompareSettings> ParseCompareSettings(const objectives::EvalInput& in,
                                                     int default_settle_cycles,
                                                     const std::vector<std::string>& known_channels,
                                                     const std::string& robot) {
  CompareSettings s;
  if (auto st = ParseParams(in, default_settle_cycles, s); !st.ok()) return st;
  for (const auto& [name, value] : in.options) {
    if (name == "error") {
      if (value == "shape") s.mode = Mode::kShape;
      else if (value == "pointwise") s.mode = Mode::kPointwise;
      else if (value == "stats") s.mode = Mode::kStats;
      else if (value == "acceleration") s.mode = Mode::kAcceleration;
      else
        return absl::InvalidArgumentError(absl::StrCat(
            "option error = '", value, "' is not one of shape, pointwise, stats, acceleration"));
    } else if (name == "metric") {
      auto m = ParseMetric(value);
      if (!m.ok()) return absl::InvalidArgumentError(absl::StrCat("option ", m.status().message()));
      s.metric = *m;
    } else if (name == "channels") {
      if (auto st = ParseChannels(value, known_channels, robot, s); !st.ok()) return st;
    } else if (name == "weights") {
      if (auto st = ParseWeights(value, s); !st.ok()) return st;
    } else {
      return absl::InvalidArgumentError(
          absl::StrCat("unknown option ", name, " (known: error, metric, channels, weights)"));
    }
  }
  return s;
}

absl::StatusOr<Comparison> CompareRecording(const recording::Recording& rec, double period,
                                            double offset, const CompareSettings& s,
                                            const Simulator& simulate) {
  if (auto st = CheckShape(rec); !st.ok()) return st;
  const size_t n = rec.t.size();
  const double dt = rec.dt > 0 ? rec.dt : (rec.t.back() - rec.t.front()) / (n - 1);
  if (!(dt > 0) || !std::isfinite(dt)) return absl::InvalidArgumentError("no sampling interval");
  // The simulated run: from rest, to past the recording's end.
  const bool periodic = period > 0;
  if (!periodic && (s.mode == Mode::kShape || s.mode == Mode::kStats))
    return absl::InvalidArgumentError(
        "error = shape and stats average over gait cycles: a command that does not repeat (a "
        "playback) compares with error = pointwise or acceleration");
  const double settle_t = periodic ? s.settle_cycles * period : 0;
  double last = rec.t.back() + offset;
  if (s.mode == Mode::kAcceleration && s.window_s > 0)  // what the window compares
    last = std::min(last, rec.t.front() + s.window_s + offset);
  if (last <= settle_t)
    return absl::InvalidArgumentError(absl::StrCat("the recording ends at simulated time ", last,
                                                   " s, within the ", s.settle_cycles,
                                                   " settle cycles of ", period, " s"));
  const int margin = s.mode == Mode::kAcceleration ? kSavitzkyGolayHalfWindow : 0;
  double duration = last + (s.max_shift + 2 + margin) * dt;
  if (periodic) {
    const double cycles = std::ceil((duration + period) / period);
    if (cycles > 1e6) return absl::InvalidArgumentError("the recording spans over 1e6 gait cycles");
    duration = cycles * period;
  }
  // Samples at the recording's interval, or finer by a whole factor when it spans at least
  // two timesteps per sample (less interpolation error; the recorded times stay on the grid).
  const int oversample = std::max(1, static_cast<int>(std::floor(dt / (2 * s.timestep_s) + 1e-9)));
  const SimRun run = simulate(duration, oversample / dt);
  if (!run.valid) return absl::AbortedError(absl::StrCat("simulation: ", run.reason));
  const Trajectory& sim = run.trajectory;
  if (sim.t.size() < 2) return absl::InternalError("the simulation recorded no samples");
  auto channels = ChosenChannels(rec, sim, s);
  if (!channels.ok()) return channels.status();
  const int bins = periodic ? BinsPerPeriod(period, dt) : 0;
  const auto [kb, ke] = periodic ? RecordedCycles(rec, period, bins, s.settle_cycles)
                                 : std::pair<int64_t, int64_t>{0, 0};
  Context c{rec, sim,      s,    std::move(*channels), {}, period, offset,
            dt,  settle_t, bins, rec.t.front(),        kb, ke,     {}};
  c.out.simulated_s = run.simulated_s;
  c.out.period_s = period;
  for (size_t k = 0; k < rec.channels.size(); ++k) {
    const int at = sim.Index(rec.channels[k]);
    if (at >= 0 && AxisOf(rec.channels[k]) == 0)
      c.x_channels.push_back({rec.channels[k], static_cast<int>(k), at, 0});
  }
  if (s.mode == Mode::kAcceleration) {
    if (auto st = Accelerations(c); !st.ok()) return st;
    return c.out;
  }
  if (s.mode == Mode::kStats) {
    if (auto st = Stats(c); !st.ok()) return st;
    return c.out;
  }
  if (s.mode == Mode::kShape) {
    if (c.kb >= c.ke) return c.NoCycles();
    const int shift = std::min(s.max_shift, bins / 2);
    double fine = 0;
    const auto best = ShapeError(rec, sim, c.channels, period, bins, c.origin, offset, c.kb, c.ke,
                                 shift, s.metric, nullptr, &fine);
    c.out.error = best.error;
    c.out.shift = best.shift;
    c.out.time_shift_s = best.shift * period / bins + fine;
    c.AddOffsets(c.channels, best.offsets);
  } else if (auto st = Pointwise(c); !st.ok()) {
    return st;
  }
  Distance(c, c.out.time_shift_s);
  return c.out;
}

objectives::EvalResult CompareAll(
    const objectives::EvalInput& in, const CompareSettings& s, const std::string& objective,
    const std::function<absl::StatusOr<Comparison>(const recording::Recording&)>& compare) {
  objectives::EvalResult r;
  if (in.recordings.empty()) {
    r.reason = absl::StrCat(objective, " needs at least one recording");
    return r;
  }
  if (!s.weights.empty() && s.weights.size() != in.recordings.size()) {
    r.reason = absl::StrCat("option weights: ", s.weights.size(), " weights for ",
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
    auto c = compare(*in.recordings[i]);
    if (!c.ok()) {
      r.reason = absl::StrCat("recording ", i, ": ", c.status().message());
      r.metrics["simulated_s"] = simulated;
      return r;
    }
    simulated += c->simulated_s;
    const double w = s.weights.empty() ? 1.0 : s.weights[i];
    sum += w * c->error;
    weight_sum += w;
    const std::string k = absl::StrCat(i);
    r.metrics["error_" + k] = c->error;
    r.metrics["best_shift_" + k] = c->shift;
    r.metrics["time_shift_s_" + k] = c->time_shift_s;
    r.metrics["period_s_" + k] = c->period_s;
    if (c->has_distance) {
      r.metrics["sim_distance_per_cycle_" + k] = c->sim_distance;
      r.metrics["real_distance_per_cycle_" + k] = c->real_distance;
      if (std::fabs(c->sim_distance) > 1e-12)
        r.metrics["distance_ratio_" + k] = c->real_distance / c->sim_distance;
    }
    for (int a = 0; a < 3; ++a) {
      offset_sum[a] += c->offset_sum[a];
      offset_count[a] += c->offset_count[a];
    }
  }
  const char* axis_names[3] = {"offset_x", "offset_y", "offset_z"};
  for (int a = 0; a < 3; ++a)
    if (offset_count[a] > 0) r.metrics[axis_names[a]] = offset_sum[a] / offset_count[a];
  const double error = sum / weight_sum;
  r.metrics["error"] = error;
  if (s.mode == Mode::kAcceleration) r.metrics["acceleration_fitness"] = 1 - error;  // paper 004's F
  r.metrics["simulated_s"] = simulated;
  r.valid = true;
  r.fitness = -error;
  return r;
}

}  // namespace gaitforge::calibration
