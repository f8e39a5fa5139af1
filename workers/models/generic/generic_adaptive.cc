// Paper 004's adaptive model on a generic robot (generic_adaptive.h).
#include "workers/models/generic/generic_adaptive.h"

#include <cmath>
#include <limits>
#include <thread>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "services/engines/sweep/nelder_mead.h"
#include "workers/models/generic/generic_playback.h"
#include "workers/objectives/calibration_error.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::generic {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// m of error per (relative change of a parameter from its start)^2: a tie-breaker that keeps
// a parameter the recordings do not move (an axis a recording does not bend) where it
// started instead of drifting; 10% costs 1e-6 m, far below the errors fitted.
constexpr double kPull = 1e-4;

// The mean PlaybackError over recs with `names` set to x; infinite when one is invalid.
double MeanError(const robots::RobotDescriptor& d, const ParamValues& base,
                 const std::vector<const recording::Recording*>& recs,
                 const std::vector<std::string>& names, const std::vector<double>& x,
                 double from_fraction, int threads) {
  ParamValues v = base;
  for (size_t i = 0; i < names.size(); ++i)
    if (!v.Set(names[i], x[i]).ok()) return kInf;
  std::vector<double> errors(recs.size());
  const auto part = [&](size_t t, size_t n) {
    sim::InitThread();
    for (size_t i = t; i < recs.size(); i += n) errors[i] = PlaybackError(d, v, *recs[i], from_fraction);
  };
  const size_t n = std::max<size_t>(1, std::min<size_t>(threads, recs.size()));
  std::vector<std::thread> pool;
  for (size_t t = 1; t < n; ++t) pool.emplace_back(part, t, n);
  part(0, n);
  for (auto& th : pool) th.join();
  double sum = 0;
  for (double e : errors) sum += e;  // in order: the same for any number of threads
  return sum / recs.size();
}

}  // namespace

double PlaybackError(const robots::RobotDescriptor& d, const ParamValues& v,
                     const recording::Recording& rec, double from_fraction) {
  const double rate = 1.0 / rec.dt;
  const calibration::SimRun run = SimulatePlayback(d, v, rec, 0, rec.t.back() + 1e-9, rate);
  if (!run.valid) return kInf;
  double sum = 0;
  int64_t n = 0;
  for (const robots::Sensor& s : d.sensors) {
    if (s.kind != "marker") continue;
    for (const std::string& marker : s.names)
      for (const std::string& axis : s.axes) {
        const std::string channel = absl::StrCat(marker, ".", axis);
        const int c = rec.ChannelIndex(channel), k = run.trajectory.Index(channel);
        if (c < 0 || k < 0) continue;
        for (size_t i = 0; i < rec.t.size(); ++i) {
          if (rec.t[i] < rec.t.front() + from_fraction * (rec.t.back() - rec.t.front())) continue;
          const double sim = calibration::Interpolate(run.trajectory.t, run.trajectory.columns[k], rec.t[i]);
          sum += std::pow(rec.columns[c][i] - sim, 2);
          ++n;
        }
      }
  }
  return n > 0 ? std::sqrt(sum / n) : kInf;
}

absl::StatusOr<ParameterFit> FitParameters(const robots::RobotDescriptor& d, const ParamValues& base,
                                           const std::vector<const recording::Recording*>& recs,
                                           const std::vector<std::string>& names,
                                           int max_evaluations, double from_fraction,
                                           int threads) {
  engines::Bounds bounds;
  std::vector<double> x0, steps;
  for (const std::string& n : names) {
    const robots::Parameter* p = d.FindParameter(n);
    if (p == nullptr) return absl::InvalidArgumentError(absl::StrCat("'", n, "' is not a parameter of ", d.name));
    bounds.lo.push_back(p->lo);
    bounds.hi.push_back(p->hi);
    x0.push_back(base(n));
    steps.push_back(0.25 * std::max(std::abs(base(n)), 0.05 * (p->hi - p->lo)));
  }
  const auto evaluate = [&](const std::vector<double>& x) {
    double e = MeanError(d, base, recs, names, x, from_fraction, threads);
    for (size_t i = 0; i < x.size(); ++i)
      if (x0[i] != 0) e += kPull * std::pow((x[i] - x0[i]) / x0[i], 2);
    engines::Evaluation ev;
    ev.valid = std::isfinite(e);
    ev.fitness = ev.valid ? -e : 0;
    if (!ev.valid) ev.reason = "the playback diverged";
    return ev;
  };
  engines::sweep::NelderMead nm(x0, evaluate(x0), steps, bounds);
  ParameterFit fit;
  fit.evaluations = 1;
  while (!nm.done() && fit.evaluations < max_evaluations) {
    std::vector<engines::Evaluation> evals;
    for (const auto& x : nm.pending()) evals.push_back(evaluate(x));
    fit.evaluations += static_cast<int>(evals.size());
    nm.Tell(evals, bounds, 1000000, 1e-6);
  }
  if (!nm.best_eval().valid) return absl::FailedPreconditionError("no parameters in range play the recordings back");
  fit.values = nm.best();
  fit.error_m = MeanError(d, base, recs, names, fit.values, from_fraction, threads);
  return fit;
}

absl::StatusOr<std::vector<double>> RecordingState(const recording::Recording& rec,
                                                   const std::vector<std::string>& inputs) {
  std::vector<double> state;
  const size_t half = rec.t.size() / 2, last = rec.t.size() - 1;
  for (const std::string& input : inputs) {
    const bool rate = absl::EndsWith(input, ".rate");
    const std::string channel = rate ? input.substr(0, input.size() - 5) : input;
    const int c = rec.ChannelIndex(channel);
    if (c < 0) return absl::InvalidArgumentError(absl::StrCat("the recording has no channel '", channel, "'"));
    const std::vector<double>& col = rec.columns[c];
    if (rate) {
      state.push_back((col[last] - col[half]) / std::max(1e-12, rec.t[last] - rec.t[half]));
      continue;
    }
    double sum = 0;
    for (size_t i = half; i <= last; ++i) sum += col[i];
    state.push_back(sum / (last - half + 1));
  }
  return state;
}

absl::StatusOr<AdaptiveModel> LearnAdaptiveModel(const robots::RobotDescriptor& d,
                                                 const ParamValues& base,
                                                 const std::vector<const recording::Recording*>& recs,
                                                 const std::vector<std::string>& inputs,
                                                 const std::vector<std::string>& names,
                                                 int max_evaluations,
                                                 const learned::TrainOptions& train, int threads) {
  AdaptiveModel m;
  std::vector<std::vector<double>> x, y;
  for (const recording::Recording* rec : recs) {
    auto state = RecordingState(*rec, inputs);
    if (!state.ok()) return state.status();
    x.push_back(*state);
  }
  // The constant model first: where a recording does not show a parameter (an axis it does
  // not bend), its fit keeps the value all recordings agree on.
  auto constant = FitParameters(d, base, recs, names, max_evaluations, 0, threads);
  if (!constant.ok()) return constant.status();
  m.constant = *constant;
  ParamValues start = base;
  for (size_t i = 0; i < names.size(); ++i)
    if (auto s = start.Set(names[i], constant->values[i]); !s.ok()) return s;
  // The recordings' fits are independent: spread over the threads, each its own ODE thread.
  std::vector<absl::StatusOr<ParameterFit>> fits(recs.size(), absl::UnknownError("not run"));
  std::vector<std::thread> pool;
  const size_t n_threads = std::max<size_t>(1, std::min<size_t>(threads, recs.size()));
  for (size_t t = 0; t < n_threads; ++t)
    pool.emplace_back([&, t] {
      sim::InitThread();
      for (size_t i = t; i < recs.size(); i += n_threads)
        fits[i] = FitParameters(d, start, {recs[i]}, names, max_evaluations, 0.5);
    });
  for (auto& th : pool) th.join();
  for (auto& fit : fits) {
    if (!fit.ok()) return fit.status();
    y.push_back(fit->values);
    m.per_recording.push_back(*fit);
  }
  auto mlp = learned::Train(inputs, names, x, y, train, &m.report);
  if (!mlp.ok()) return mlp.status();
  m.mlp = *mlp;
  return m;
}

}  // namespace gaitforge::generic
