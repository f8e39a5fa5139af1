// Paper 004's tracking on a generic robot (generic_tracking.h).
#include "workers/models/generic/generic_tracking.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "absl/strings/str_cat.h"
#include "workers/models/generic/generic_run.h"
#include "workers/objectives/calibration_error.h"

namespace gaitforge::generic {
namespace {

constexpr const char* kAxisNames[] = {"x", "y", "z"};

// The tracking section's numbers with values v, and each actuator's rod-length map.
struct Loop {
  double kp, ki, kd, lever, rate_hz, lead_s;
  std::vector<std::array<double, 3>> attach;  // per actuator; zero: not steered
  std::vector<double> max_force;              // per actuator, N (infinite: not a tendon)
};

Loop LoopOf(const robots::RobotDescriptor& d, const ParamValues& v) {
  const robots::Tracking& tk = *d.tracking;
  const auto value = [&v](const std::string& n) { return v(n); };
  Loop l{tk.kp.Eval(value),     tk.ki.Eval(value),      tk.kd.Eval(value),
         tk.lever.Eval(value),  tk.rate_hz.Eval(value), tk.lead_s.Eval(value), {}, {}};
  for (const robots::Actuator& a : d.actuators) {
    std::array<double, 3> at{};
    double cap = std::numeric_limits<double>::infinity();
    if (a.type == "tendon") {
      for (int i = 0; i < 3; ++i) at[i] = a.attach2[i].Eval(value);
      cap = a.max_force.Eval(value);
    }
    l.attach.push_back(at);
    l.max_force.push_back(cap);
  }
  return l;
}

// Each actuator's rod-length error (m) for the marker's error e on the steered axes.
std::vector<double> RodErrors(const robots::Tracking& tk, const Loop& l, const std::vector<double>& e) {
  std::vector<double> dl(l.attach.size(), 0.0);
  for (size_t k = 0; k < dl.size(); ++k)
    for (size_t a = 0; a < tk.axes.size(); ++a) dl[k] += l.attach[k][tk.axes[a]] * e[a] / l.lever;
  return dl;
}

// The reference at path time tau: eased from `rest` to the path's start during the lead-in.
std::vector<double> ReferenceAt(const Path& p, const std::vector<double>& rest, double tau,
                                double lead_s) {
  std::vector<double> r(p.axes.size());
  for (size_t a = 0; a < r.size(); ++a) {
    const double start = p.axes[a].front();
    if (tau >= 0) {
      r[a] = calibration::Interpolate(p.t, p.axes[a], tau);
    } else {
      const double s = lead_s > 0 ? std::clamp(1.0 + tau / lead_s, 0.0, 1.0) : 1.0;
      r[a] = rest[a] + (start - rest[a]) * 0.5 * (1 - std::cos(M_PI * s));
    }
  }
  return r;
}

// The errors over the path's ticks (t >= 0) into r's summary figures.
void Summarise(TrackingResult& r, double dt) {
  double sum = 0;
  int n = 0;
  for (size_t i = 0; i < r.t.size(); ++i) {
    if (r.t[i] < -1e-9) continue;
    double e2 = 0;
    for (size_t a = 0; a < r.reference.size(); ++a)
      e2 += std::pow(r.reference[a][i] - r.position[a][i], 2);
    r.max_error_m = std::max(r.max_error_m, std::sqrt(e2));
    r.iste += std::max(0.0, r.t[i]) * e2 * dt;
    sum += e2;
    ++n;
  }
  r.rms_error_m = n > 0 ? std::sqrt(sum / n) : 0;
}

// The PID's state across ticks.
struct Pid {
  std::vector<double> integral, previous;
  bool first = true;
  std::vector<double> Correction(const Loop& l, const std::vector<double>& dl) {
    const double dt = 1.0 / l.rate_hz;
    if (first) integral.assign(dl.size(), 0.0), previous = dl;
    std::vector<double> out(dl.size());
    for (size_t k = 0; k < dl.size(); ++k) {
      integral[k] += dl[k] * dt;
      out[k] = l.kp * dl[k] + l.ki * integral[k] + (first ? 0.0 : l.kd * (dl[k] - previous[k]) / dt);
    }
    previous = dl;
    first = false;
    return out;
  }
};

// Over every tick, the lead-in included: each actuator's rod-length error (m) and the RMS
// distance from the reference (m).
std::vector<std::vector<double>> TickRodErrors(const robots::Tracking& tk, const Loop& l,
                                               const TrackingResult& r, double* rms) {
  std::vector<std::vector<double>> dl;
  double sum = 0;
  for (size_t i = 0; i < r.t.size(); ++i) {
    std::vector<double> e(r.reference.size());
    for (size_t a = 0; a < e.size(); ++a) {
      e[a] = r.reference[a][i] - r.position[a][i];
      sum += e[a] * e[a];
    }
    dl.push_back(RodErrors(tk, l, e));
  }
  *rms = std::sqrt(sum / std::max<size_t>(1, r.t.size()));
  return dl;
}

// base + gain x dl `lead` ticks ahead, averaged over +-0.05 s of ticks, clamped to
// max_force.
using Ticks = std::vector<std::vector<double>>;  // [tick][actuator]
Ticks Corrected(const Ticks& base, const Ticks& dl, double gain, int lead, const Loop& l) {
  const int n = static_cast<int>(dl.size());
  const int half = std::max(1, static_cast<int>(std::lround(0.05 * l.rate_hz)));
  Ticks out(n, std::vector<double>(l.attach.size(), 0.0));
  for (int i = 0; i < n; ++i)
    for (size_t k = 0; k < l.attach.size(); ++k) {
      double sum = 0;
      int count = 0;
      for (int j = i + lead - half; j <= i + lead + half; ++j, ++count)
        sum += dl[std::clamp(j, 0, n - 1)][k];
      const double b = base.empty() ? 0.0 : base[std::min<size_t>(i, base.size() - 1)][k];
      out[i][k] = std::clamp(b + gain * sum / count, -l.max_force[k], l.max_force[k]);
    }
  return out;
}

// How many ticks the model takes to go half way to where a step of force takes it: the
// lead of the feed-forward's corrections. The step: a tenth of the first tendon's
// max_force, from rest, held for 2 s.
int ResponseTicks(const robots::RobotDescriptor& d, const ParamValues& model, const Loop& l,
                  const TrackingOptions& o);

}  // namespace

absl::StatusOr<FeedForward> LearnFeedForward(const robots::RobotDescriptor& d,
                                             const ParamValues& model, const Path& path,
                                             int iterations, const TrackingOptions& o) {
  if (!d.tracking)
    return absl::InvalidArgumentError(absl::StrCat("robot ", d.name, " has no tracking section"));
  constexpr double kFirstGain = 100;  // N per m of rod-length error; adapted run by run
  const Loop l = LoopOf(d, model);
  TrackingOptions open = o;
  open.feedback = false;
  FeedForward ff, best;
  Ticks best_dl;
  double best_score = std::numeric_limits<double>::infinity(), gain = kFirstGain;
  const int lead = ResponseTicks(d, model, l, open);
  for (int j = 0; j < iterations; ++j) {
    const TrackingResult run = Track(d, model, path, &ff, open);
    best.iterations = j + 1;
    if (!run.valid && best_dl.empty())
      return absl::FailedPreconditionError("the model cannot run the path: " + run.reason);
    double score = std::numeric_limits<double>::infinity();
    Ticks dl;
    if (run.valid) dl = TickRodErrors(*d.tracking, l, run, &score);
    if (score < best_score) {
      best_score = score;
      best.forces = ff.forces.empty() ? Ticks(dl.size(), std::vector<double>(l.attach.size(), 0.0))
                                      : ff.forces;
      best.residual_rms_m = run.rms_error_m;
      best.residual_max_m = run.max_error_m;
      best_dl = dl;
      gain *= 1.3;
    } else {
      gain *= 0.5;
    }
    ff.forces = Corrected(best.forces, best_dl, gain, lead, l);
  }
  return best;
}

absl::StatusOr<Path> PathOf(const robots::RobotDescriptor& d, const recording::Recording& rec,
                            const std::string& name) {
  if (!d.tracking)
    return absl::InvalidArgumentError(absl::StrCat("robot ", d.name, " has no tracking section"));
  Path p;
  p.t = rec.t;
  for (int axis : d.tracking->axes) {
    const std::string column = absl::StrCat(d.tracking->marker, ".", kAxisNames[axis]);
    const int c = rec.ChannelIndex(column);
    if (c < 0)
      return absl::InvalidArgumentError(absl::StrCat(
          name, ": no column '", column, "', the tracked marker's ", kAxisNames[axis],
          " (robot ", d.name, " tracks ", d.tracking->marker, ")"));
    p.axes.push_back(rec.columns[c]);
  }
  const double t0 = p.t.front();
  for (double& t : p.t) t -= t0;
  return p;
}

TrackingResult Track(const robots::RobotDescriptor& d, const ParamValues& v, const Path& path,
                     const FeedForward* ff, const TrackingOptions& o) {
  TrackingResult r;
  if (!d.tracking) {
    r.reason = absl::StrCat("robot ", d.name, " has no tracking section (docs/robots.md)");
    return r;
  }
  const robots::Tracking& tk = *d.tracking;
  const Loop l = LoopOf(d, v);
  const size_t axes = tk.axes.size(), acts = d.actuators.size();
  r.reference.resize(axes);
  r.position.resize(axes);
  r.command.resize(acts);
  int64_t every = 1, tick = 0;
  double h = 0;
  std::vector<double> rest, command(acts, 0.0);
  Pid pid;
  const auto steps = [&](const RobotWorld& w) -> int64_t {
    h = w.timestep();
    const double per_tick = 1.0 / (l.rate_hz * h);
    every = std::llround(per_tick);
    if (every < 1 || std::abs(per_tick - static_cast<double>(every)) > 1e-6) {
      r.reason = absl::StrCat("tracking.rate_hz ", l.rate_hz, " Hz is not a whole number of ",
                              h, " s timesteps");
      return 0;
    }
    return static_cast<int64_t>(std::ceil((l.lead_s + path.t.back()) / h - 1e-9));
  };
  const auto each = [&](const RobotWorld& w, int64_t i) {
    if (i % every != 0) return;
    std::vector<double> y(axes);
    for (size_t a = 0; a < axes; ++a)
      y[a] = *w.Channel(absl::StrCat(tk.marker, ".", kAxisNames[tk.axes[a]]));
    if (rest.empty()) rest = y;
    const double tau = static_cast<double>(i) * h - l.lead_s;
    const std::vector<double> ref = ReferenceAt(path, rest, tau, l.lead_s);
    std::vector<double> e(axes);
    for (size_t a = 0; a < axes; ++a) {
      e[a] = ref[a] - y[a];
      r.reference[a].push_back(ref[a]);
      r.position[a].push_back(y[a]);
    }
    r.t.push_back(tau);
    const std::vector<double> pid_out =
        o.feedback ? pid.Correction(l, RodErrors(tk, l, e)) : std::vector<double>(acts, 0.0);
    for (size_t k = 0; k < acts; ++k) {
      double f = pid_out[k];
      if (ff != nullptr && !ff->forces.empty())
        f += ff->forces[std::min<size_t>(tick, ff->forces.size() - 1)][k];
      command[k] = std::clamp(f, -l.max_force[k], l.max_force[k]);
      r.command[k].push_back(command[k]);
    }
    ++tick;
  };
  const auto source = [&](const RobotWorld&) -> Source {
    return [&](int64_t, std::vector<double>& out) { out = command; };
  };
  double simulated = 0;
  const bool ran = RunWorld(d, v, o.timestep_s, o.engine, steps, each, source, &r.reason, &simulated);
  if (!ran || !r.reason.empty()) {
    if (r.reason.empty()) r.reason = "the simulation failed";
    if (ran) return r;
    r.reason = absl::StrCat(r.reason, " (at ", simulated, " s)");
    return r;
  }
  Summarise(r, 1.0 / l.rate_hz);
  r.valid = true;
  return r;
}

}  // namespace gaitforge::generic

namespace gaitforge::generic {
namespace {

int ResponseTicks(const robots::RobotDescriptor& d, const ParamValues& model, const Loop& l,
                  const TrackingOptions& o) {
  size_t tendon = 0;
  while (tendon < l.attach.size() && !std::isfinite(l.max_force[tendon])) ++tendon;
  const double lead_s = l.lead_s, duration = 2.0;
  Path still{{0.0, duration}, std::vector<std::vector<double>>(d.tracking->axes.size(), {0.0, 0.0})};
  const int ticks = static_cast<int>(std::lround((lead_s + duration) * l.rate_hz)) + 1;
  FeedForward step;
  step.forces.assign(ticks, std::vector<double>(l.attach.size(), 0.0));
  const int start = static_cast<int>(std::lround(lead_s * l.rate_hz));
  for (int i = start; i < ticks && tendon < l.attach.size(); ++i)
    step.forces[i][tendon] = 0.1 * l.max_force[tendon];
  const TrackingResult r = Track(d, model, still, &step, o);
  const auto moved = [&r, start](size_t i) {
    double s = 0;
    for (const auto& axis : r.position) s += std::pow(axis[i] - axis[start], 2);
    return std::sqrt(s);
  };
  if (!r.valid || r.t.size() <= static_cast<size_t>(start) + 1) return 1;
  const double half = 0.5 * moved(r.t.size() - 1);
  for (size_t i = start; i < r.t.size(); ++i)
    if (moved(i) >= half) return std::max(1, static_cast<int>(i) - start);
  return 1;
}

}  // namespace
}  // namespace gaitforge::generic
