// gaitforge-sim plan (sim_plan.h).
#include "workers/tools/sim_plan.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <mutex>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "robots/controllers.h"
#include "services/core/file_text.h"
#include "services/core/json_text.h"
#include "services/diagnosis/plan.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/models/generic/generic_playback.h"
#include "workers/objectives/calibration_error.h"
#include "workers/tools/sim_tool.h"

namespace gaitforge::simtool {
namespace {

namespace plan = diagnosis::plan;
using core::JsonNum;
using core::JsonQuote;

// What every candidate is simulated and compared with.
struct Setting {
  std::vector<plan::Explanation> explanations;
  std::vector<generic::ParamValues> values;  // per explanation
  std::vector<plan::Recorded> recorded;
  std::vector<recording::Recording> playbacks;  // the recordings, when they are playbacks
  std::vector<std::string> channels;  // asked for ("": decided on the first simulation)
  std::vector<std::string> recorded_channels;
  double rate_hz = 100;
  double residual = 0;  // the smallest training error of any explanation
};

// A plan compares every recording with one model at one rate: a recording of another robot,
// or sampled at another rate than the first (beyond 1%), is refused, as the coordinator
// refuses it in a diagnosis (services/coordinator/recordings.cc).
absl::Status SameRobotAndRate(const recording::Recording& rec, const std::string& path,
                              const GenericRun& run, const std::string& first, double first_dt) {
  if (rec.meta.robot != run.robot->name)
    return absl::InvalidArgumentError(absl::StrCat(
        "--recordings ", path, ": a recording of robot '", rec.meta.robot, "', the spec's robot is '",
        run.robot->name, "': one plan is for one robot"));
  if (!first.empty() && !recording::SameRate(rec.dt, first_dt))
    return absl::InvalidArgumentError(absl::StrCat(
        "--recordings ", path, ": sampled every ", rec.dt, " s, ", first, " every ", first_dt,
        " s: a plan's recordings share a rate (resample them to one)"));
  return absl::OkStatus();
}

// The recordings' gaits (or playbacks: all of one kind) and their sampling rate (made a
// whole number of the model's steps).
absl::Status ReadRecorded(const GenericRun& run, const PlanArgs& a, double timestep_s,
                          Setting* s) {
  std::string kind, first;
  double first_dt = 0;
  for (const auto& part : absl::StrSplit(a.recordings, ',', absl::SkipEmpty())) {
    const std::string path(part);
    auto rec = ReadRecording(path, run);
    if (!rec.ok()) return rec.status();
    if (auto st = SameRobotAndRate(*rec, path, run, first, first_dt); !st.ok()) return st;
    if (first.empty()) first = path, first_dt = rec->dt;
    const std::string k = rec->meta.command_kind;
    if ((k != "gait" && k != "playback") || (!kind.empty() && k != kind))
      return absl::InvalidArgumentError(absl::StrCat(
          "--recordings ", path, ": its command is a ", k, kind.empty() ? "" : " after a " + kind,
          "; a plan varies gaits or playbacks, recordings of one kind"));
    kind = k;
    const std::string name = path.substr(path.find_last_of('/') + 1);
    if (k == "playback") {
      s->recorded.push_back({name, {}, 0});
      s->playbacks.push_back(*rec);
    } else {
      const double period = robots::FindControllerKind(run.robot->controller.kind)->period_s(rec->meta.genes);
      s->recorded.push_back({name, rec->meta.genes, std::max(1, static_cast<int>(std::lround(rec->t.back() / period)))});
    }
    if (s->recorded.size() == 1) {
      s->recorded_channels = rec->channels;
      const double steps = std::max(1.0, std::ceil(rec->dt / timestep_s - 1e-9));
      s->rate_hz = 1.0 / (steps * timestep_s);
    }
  }
  if (s->recorded.empty())
    return absl::InvalidArgumentError("--recordings: give the diagnosis's recordings");
  return absl::OkStatus();
}

absl::StatusOr<Setting> Prepare(const GenericRun& run, const PlanArgs& a) {
  if (auto st = plan::Check(a.options); !st.ok()) return st;
  auto report = core::ReadWholeFile(a.options.report);
  if (!report.ok()) return absl::NotFoundError(absl::StrCat("--report: ", report.status().message()));
  Setting s;
  auto explanations = plan::ExplanationsFromReport(*report, a.options.report, a.options.rivals);
  if (!explanations.ok()) return explanations.status();
  s.explanations = *std::move(explanations);
  auto base = RunValues(run);
  if (!base.ok()) return base.status();
  s.residual = INFINITY;
  for (const plan::Explanation& e : s.explanations) {
    generic::ParamValues v = *base;
    for (const auto& [name, value] : e.set)
      if (auto st = v.Set(name, value); !st.ok())
        return absl::InvalidArgumentError(absl::StrCat(a.options.report, ": explanation ", e.id, ": ",
                                                       st.message()));
    s.values.push_back(std::move(v));
    if (std::isfinite(e.train) && e.train > 0) s.residual = std::min(s.residual, e.train);
  }
  if (!std::isfinite(s.residual))
    return absl::InvalidArgumentError(absl::StrCat(a.options.report, ": no training error to measure "
                                                   "the separations against"));
  if (auto st = ReadRecorded(run, a, (*base)("simulation.timestep_s"), &s); !st.ok()) return st;
  s.channels = absl::StrSplit(a.channels, ',', absl::SkipEmpty());
  return s;
}

// The compared channels' indices in tr: those asked for (an error names one it lacks), or
// every channel the recordings and tr both have.
absl::StatusOr<std::vector<int>> Compared(const Setting& s, const calibration::Trajectory& tr) {
  std::vector<int> idx;
  for (const std::string& c : s.channels.empty() ? s.recorded_channels : s.channels) {
    const int i = tr.Index(c);
    if (i < 0 && !s.channels.empty())
      return absl::InvalidArgumentError(absl::StrCat("--channels: the model gives no channel ", c));
    if (i >= 0) idx.push_back(i);
  }
  if (idx.empty())
    return absl::InvalidArgumentError("the recordings and the model have no channel in common");
  return idx;
}

struct Scored {
  plan::Experiment e;
  double period_s = 0;  // 0: a playback
  double duration_s = 0;
  std::vector<double> separation{};  // per pair, the channels' pooled RMS difference
  std::string reason{};            // why a simulation failed ("" when none did)
};

// Pooled RMS difference of a and b over the compared channels after the first cycle, each
// channel's constant difference profiled out (the diagnosis fits a recording's offsets), at
// the best of the time shifts up to max_shift samples (the diagnosis's shift search): what a
// shift or an offset absorbs does not tell explanations apart.
double Separation(const calibration::Trajectory& a, const calibration::Trajectory& b,
                  const std::vector<int>& idx, double period_s, int max_shift) {
  const size_t n = std::min(a.t.size(), b.t.size());
  size_t begin = 0;
  while (begin + 1 < n && a.t[begin] < period_s) ++begin;
  calibration::Signals x, y;
  for (int i : idx) {
    x.emplace_back(a.columns[i].begin() + begin, a.columns[i].begin() + n);
    y.emplace_back(b.columns[i].begin() + begin, b.columns[i].begin() + n);
  }
  const int shift = std::min(max_shift, static_cast<int>((n - begin) / 4));
  return calibration::ShiftInvariantError(calibration::Metric::kRmse, x, y, shift, true).error;
}

// A playback's recording with its inputs varied (plan.h, InputVariant).
recording::Recording Varied(const recording::Recording& rec, const plan::InputVariant& v,
                            const std::vector<std::string>& inputs) {
  recording::Recording out = rec;
  for (double& t : out.t) t *= v.time_scale;
  const double release = v.release_at > 0 && v.release_at < 1 ? v.release_at * out.t.back() : INFINITY;
  for (const std::string& name : inputs) {
    const int c = out.ChannelIndex(name);
    if (c < 0) continue;
    for (size_t i = 0; i < out.t.size(); ++i) out.columns[c][i] = out.t[i] < release ? v.scale * out.columns[c][i] : 0;
  }
  return out;
}

// One candidate simulated under one explanation's values: a gait from rest, or a playback
// of its recording's inputs varied; c's period and duration set.
calibration::SimRun Simulate(const GenericRun& run, const Setting& s, const generic::ParamValues& v,
                             Scored& c) {
  if (c.e.source < 0) {
    c.period_s = robots::FindControllerKind(run.robot->controller.kind)->period_s(c.e.genes);
    c.duration_s = c.period_s * c.e.cycles;
    return generic::SimulateChannels(*run.robot, v, c.e.genes, c.e.cycles, s.rate_hz);
  }
  const recording::Recording rec = Varied(s.playbacks[c.e.source], c.e.inputs, run.robot->InputChannels());
  c.duration_s = rec.t.back();
  return generic::SimulatePlayback(*run.robot, v, rec, 0, rec.t.back(), s.rate_hz);
}

absl::Status Score(const GenericRun& run, const Setting& s, int threads, int max_shift,
                   std::vector<Scored>* scored) {
  const auto pairs = plan::Pairs(static_cast<int>(s.explanations.size()));
  absl::Status bad = absl::OkStatus();
  std::mutex mu;
  ParallelFor(static_cast<int>(scored->size()), threads, [&](int k) {
    Scored& c = (*scored)[k];
    std::vector<calibration::Trajectory> runs;
    for (size_t i = 0; i < s.values.size() && c.reason.empty(); ++i) {
      auto sim = Simulate(run, s, s.values[i], c);
      if (!sim.valid) c.reason = absl::StrCat("under ", s.explanations[i].id, ": ", sim.reason);
      runs.push_back(std::move(sim.trajectory));
    }
    if (!c.reason.empty()) return;
    auto idx = Compared(s, runs[0]);
    if (!idx.ok()) {
      std::lock_guard<std::mutex> lock(mu);
      bad = idx.status();
      return;
    }
    for (const auto& [i, j] : pairs)
      c.separation.push_back(Separation(runs[i], runs[j], *idx, c.period_s, max_shift));
  });
  return bad;
}

std::string GenesJson(const robots::RobotDescriptor& d, const std::vector<double>& g) {
  std::vector<std::string> items;
  for (size_t k = 0; k < g.size(); ++k)
    items.push_back(absl::StrCat(JsonQuote(d.controller.genes[k].name), ": ", JsonNum(g[k])));
  return "{" + absl::StrJoin(items, ", ") + "}";
}

// A playback candidate's inputs: the recording they come from and how they are varied.
std::string InputsJson(const Setting& s, const Scored& c) {
  if (c.e.source < 0) return "null";
  const plan::InputVariant& v = c.e.inputs;
  const bool released = v.release_at > 0 && v.release_at < 1;
  return absl::StrCat("{\"from\": ", JsonQuote(s.recorded[c.e.source].name), ", \"scale\": ",
                      JsonNum(v.scale), ", \"time_scale\": ", JsonNum(v.time_scale),
                      ", \"release_at_s\": ", released ? JsonNum(v.release_at * c.duration_s) : "null",
                      "}");
}

std::string CandidateJson(const robots::RobotDescriptor& d, const Setting& s, const Scored& c) {
  std::vector<double> ratio;
  for (double sep : c.separation) ratio.push_back(sep / s.residual);
  return absl::StrCat("{\"name\": ", JsonQuote(c.e.name), ", \"kind\": ", JsonQuote(c.e.kind),
                      ", \"genes\": ", GenesJson(d, c.e.genes), ", \"gene_values\": ",
                      core::JsonNumList(c.e.genes), ", \"cycles\": ", c.e.cycles,
                      ", \"period_s\": ", JsonNum(c.period_s), ", \"duration_s\": ",
                      JsonNum(c.duration_s), ", \"inputs\": ", InputsJson(s, c), ", \"valid\": ",
                      c.reason.empty() ? "true" : "false", ", \"reason\": ", JsonQuote(c.reason),
                      ", \"separation\": ", core::JsonNumList(c.separation), ", \"ratio\": ",
                      core::JsonNumList(ratio), "}");
}

// Which pairs the chosen recordings decide, and by how much.
std::string PairsJson(const Setting& s, const std::vector<Scored>& scored,
                      const std::vector<int>& picked, double decisive, int* undecided) {
  const auto pairs = plan::Pairs(static_cast<int>(s.explanations.size()));
  std::vector<std::string> items;
  *undecided = 0;
  for (size_t p = 0; p < pairs.size(); ++p) {
    double best = 0;
    int by = -1;
    for (int k : picked)
      if (scored[k].separation[p] / s.residual > best) {
        best = scored[k].separation[p] / s.residual;
        by = k;
      }
    const bool decided = best >= decisive;
    if (!decided) ++*undecided;
    items.push_back(absl::StrCat(
        "{\"pair\": [", JsonQuote(s.explanations[pairs[p].first].id), ", ",
        JsonQuote(s.explanations[pairs[p].second].id), "], \"best_ratio\": ", JsonNum(best),
        ", \"by\": ", by < 0 ? "null" : JsonQuote(scored[by].e.name), ", \"decided\": ",
        decided ? "true" : "false", "}"));
  }
  return "[" + absl::StrJoin(items, ", ") + "]";
}

std::string ExplanationsJson(const Setting& s) {
  std::vector<std::string> items;
  for (const plan::Explanation& e : s.explanations) {
    std::vector<std::string> set;
    for (const auto& [name, value] : e.set) set.push_back(absl::StrCat(JsonQuote(name), ": ", JsonNum(value)));
    items.push_back(absl::StrCat("{\"id\": ", JsonQuote(e.id), ", \"train\": ", JsonNum(e.train),
                                 ", \"set\": {", absl::StrJoin(set, ", "), "}}"));
  }
  return "[" + absl::StrJoin(items, ", ") + "]";
}

}  // namespace

absl::StatusOr<std::string> GenericPlan(const GenericRun& run, const PlanArgs& a) {
  auto s = Prepare(run, a);
  if (!s.ok()) return s.status();
  const plan::Options& o = a.options;
  std::vector<Scored> scored;
  std::vector<std::string> names;
  for (const plan::Recorded& r : s->recorded) names.push_back(r.name);
  const auto experiments = s->playbacks.empty()
                               ? plan::Candidates(*run.robot, s->recorded, o.random, static_cast<uint64_t>(o.seed))
                               : plan::PlaybackCandidates(names);
  for (const auto& e : experiments) scored.push_back({e});
  if (auto st = Score(run, *s, o.threads, o.max_shift, &scored); !st.ok()) return st;
  std::vector<std::vector<double>> ratio;
  for (const Scored& c : scored) {
    ratio.emplace_back();
    for (double sep : c.separation) ratio.back().push_back(sep / s->residual);
    // A failed simulation is never proposed, nor a gait the recordings already hold (its
    // separation stays in the JSON: what the data given could already tell).
    if (!c.reason.empty() || c.e.kind == "recorded")
      ratio.back().assign(plan::Pairs(static_cast<int>(s->explanations.size())).size(), NAN);
  }
  const std::vector<int> picked = plan::Choose(ratio, o.propose, o.decisive);
  std::vector<std::string> candidates, chosen;
  for (const Scored& c : scored) candidates.push_back(CandidateJson(*run.robot, *s, c));
  for (int k : picked) chosen.push_back(candidates[k]);
  int undecided = 0;
  const std::string pairs = PairsJson(*s, scored, picked, o.decisive, &undecided);
  return absl::StrCat(
      "{\"robot\": ", JsonQuote(run.robot->name), ", \"report\": ", JsonQuote(o.report),
      ", \"explanations\": ", ExplanationsJson(*s), ", \"residual\": ", JsonNum(s->residual),
      ", \"decisive\": ", JsonNum(o.decisive), ", \"rate_hz\": ", JsonNum(s->rate_hz),
      ",\n \"plan\": [", absl::StrJoin(chosen, ",\n  "), "],\n \"pairs\": ", pairs,
      ", \"undecided\": ", undecided, ",\n \"candidates\": [", absl::StrJoin(candidates, ",\n  "),
      "]}");
}

}  // namespace gaitforge::simtool
