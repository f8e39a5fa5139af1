// gaitforge-sim track (sim_track.h).
#include "workers/tools/sim_track.h"

#include <fstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "workers/models/generic/generic_tracking.h"
#include "workers/sim/ode_runtime.h"
#include "workers/tools/sim_tool.h"

namespace gaitforge::simtool {
namespace {

constexpr const char* kAxisNames[] = {"x", "y", "z"};

absl::Status WriteTicks(const robots::RobotDescriptor& d, const generic::TrackingResult& r,
                        const std::string& out) {
  std::ofstream f(out);
  if (!f) return absl::InvalidArgumentError("--out: cannot write " + out);
  const robots::Tracking& tk = *d.tracking;
  f << "t";
  for (int axis : tk.axes) f << "," << tk.marker << "." << kAxisNames[axis] << ".ref";
  for (int axis : tk.axes) f << "," << tk.marker << "." << kAxisNames[axis];
  for (const auto& a : d.actuators) f << "," << a.InputChannel();
  f << "\n";
  for (size_t i = 0; i < r.t.size(); ++i) {
    f << absl::StrFormat("%.4f", r.t[i]);
    for (const auto& col : r.reference) f << absl::StrFormat(",%.9g", col[i]);
    for (const auto& col : r.position) f << absl::StrFormat(",%.9g", col[i]);
    for (const auto& col : r.command) f << absl::StrFormat(",%.9g", col[i]);
    f << "\n";
  }
  return f ? absl::OkStatus() : absl::InternalError("writing " + out + " failed");
}

std::string ErrorsJson(const generic::TrackingResult& r) {
  return absl::StrFormat("\"max_error_m\": %.9g, \"rms_error_m\": %.9g, \"iste\": %.9g",
                         r.max_error_m, r.rms_error_m, r.iste);
}

}  // namespace

absl::StatusOr<std::string> GenericTrack(const GenericRun& run, const TrackArgs& a) {
  const robots::RobotDescriptor& d = *run.robot;
  if (!d.tracking)
    return absl::InvalidArgumentError(absl::StrCat("--robot ", d.name,
                                                   " has no tracking section (docs/robots.md)"));
  if (a.feedforward != "none" && a.feedforward != "model")
    return absl::InvalidArgumentError("--feedforward " + a.feedforward + ": one of none, model");
  if (a.ff_iterations < 1 || a.ff_iterations > 1000)
    return absl::InvalidArgumentError(absl::StrCat("--ff-iterations ", a.ff_iterations, ": 1..1000"));
  if (a.path.empty()) return absl::InvalidArgumentError("track needs --path PATH.csv");
  auto rec = ReadRecording(a.path, run);
  if (!rec.ok()) return rec.status();
  auto path = generic::PathOf(d, *rec, a.path);
  if (!path.ok()) return path.status();
  auto plant = RunValues(run);
  if (!plant.ok()) return plant.status();
  GenericRun model_run = run;
  auto model_overrides = ParseOverrides(a.model_set);
  if (!model_overrides.ok()) return model_overrides.status();
  model_run.overrides = *model_overrides;
  model_run.learned = a.model_learned;
  auto model = RunValues(model_run);
  if (!model.ok())
    return absl::InvalidArgumentError(absl::StrCat("--model-set: ", model.status().message()));
  sim::InitThread();
  generic::TrackingOptions o;
  o.feedback = a.feedback;
  std::string json = "{";
  absl::StatusOr<generic::FeedForward> ff;
  if (a.feedforward == "model") {
    ff = generic::LearnFeedForward(d, *model, *path, a.ff_iterations, o);
    if (!ff.ok()) return absl::AbortedError(ff.status().message());
    absl::StrAppend(&json, absl::StrFormat(
        "\"feedforward\": {\"iterations\": %d, \"model_rms_error_m\": %.9g, "
        "\"model_max_error_m\": %.9g}, ", ff->iterations, ff->residual_rms_m, ff->residual_max_m));
  }
  const generic::TrackingResult r = generic::Track(d, *plant, *path, ff.ok() ? &*ff : nullptr, o);
  if (!r.valid) return absl::AbortedError("the plant cannot track the path: " + r.reason);
  if (!a.out.empty())
    if (auto s = WriteTicks(d, r, a.out); !s.ok()) return s;
  return absl::StrCat(json, ErrorsJson(r), "}");
}

}  // namespace gaitforge::simtool
