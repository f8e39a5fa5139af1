// gaitforge-sim learn-parameters (sim_learn.h).
#include "workers/tools/sim_learn.h"

#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "services/core/json_text.h"
#include "workers/models/generic/generic_adaptive.h"
#include "workers/sim/ode_runtime.h"

namespace gaitforge::simtool {
namespace {

std::vector<std::string> List(const std::string& text) {
  return absl::StrSplit(text, ',', absl::SkipEmpty());
}

absl::StatusOr<std::vector<recording::Recording>> ReadAll(const std::string& list, const GenericRun& run) {
  std::vector<recording::Recording> recs;
  for (const std::string& path : List(list)) {
    auto rec = ReadRecording(path, run);
    if (!rec.ok()) return rec.status();
    if (rec->meta.command_kind != "playback")
      return absl::InvalidArgumentError(absl::StrCat(path, ": a playback recording is needed (its "
                                                     "inputs drive the model), not a ", rec->meta.command_kind));
    recs.push_back(*std::move(rec));
  }
  return recs;
}

std::string FitJson(const generic::ParameterFit& f) {
  return absl::StrCat("{\"values\": ", core::JsonNumList(f.values), ", \"error_m\": ",
                      core::JsonNum(f.error_m), ", \"evaluations\": ", f.evaluations, "}");
}

// Each held-out recording's error under the constant and the adaptive model.
std::string HeldOutJson(const GenericRun& run, const std::vector<recording::Recording>& held,
                        const std::vector<std::string>& names, const generic::AdaptiveModel& m,
                        const generic::ParamValues& base, const std::vector<std::string>& paths) {
  generic::ParamValues constant = base, adaptive = base;
  for (size_t i = 0; i < names.size(); ++i) (void)constant.Set(names[i], m.constant.values[i]);
  adaptive.SetLearned(std::make_shared<learned::Mlp>(m.mlp));
  std::vector<std::string> rows;
  for (size_t i = 0; i < held.size(); ++i)
    rows.push_back(absl::StrCat("{\"file\": ", core::JsonQuote(paths[i]), ", \"constant_error_m\": ",
                                core::JsonNum(generic::PlaybackError(*run.robot, constant, held[i])),
                                ", \"adaptive_error_m\": ",
                                core::JsonNum(generic::PlaybackError(*run.robot, adaptive, held[i])), "}"));
  return absl::StrCat("[", absl::StrJoin(rows, ", "), "]");
}

}  // namespace

absl::StatusOr<std::string> GenericLearn(const GenericRun& run, const LearnArgs& a) {
  if (a.out.empty() || a.params.empty() || a.features.empty() || a.recordings.empty())
    return absl::InvalidArgumentError("learn-parameters needs --recordings, --params, --features and --out");
  if (!run.learned.empty())
    return absl::InvalidArgumentError("--learned: learn-parameters fits a constant model per recording; it takes no learned map");
  if (a.evaluations < 5 || a.evaluations > 100000 || a.hidden < 1 || a.hidden > 1000 || a.epochs < 1)
    return absl::InvalidArgumentError("--evaluations 5..100000, --hidden 1..1000, --epochs >= 1");
  auto recs = ReadAll(a.recordings, run);
  if (!recs.ok()) return recs.status();
  auto held = ReadAll(a.held_out, run);
  if (!held.ok()) return held.status();
  auto base = RunValues(run);
  if (!base.ok()) return base.status();
  std::vector<const recording::Recording*> ptrs;
  for (const auto& r : *recs) ptrs.push_back(&r);
  learned::TrainOptions train;
  train.hidden = {a.hidden};
  train.epochs = a.epochs;
  const std::vector<std::string> names = List(a.params);
  sim::InitThread();
  auto m = generic::LearnAdaptiveModel(*run.robot, *base, ptrs, List(a.features), names, a.evaluations, train,
                                        a.threads);
  if (!m.ok()) return m.status();
  std::ofstream out(a.out);
  if (!(out << m->mlp.ToJson())) return absl::InvalidArgumentError("--out: cannot write " + a.out);
  std::vector<std::string> fits;
  for (const auto& f : m->per_recording) fits.push_back(FitJson(f));
  const learned::TrainReport& r = m->report;
  return absl::StrCat(
      "{\"params\": ", core::JsonStringList(names), ", \"per_recording\": [", absl::StrJoin(fits, ", "),
      "], \"constant\": ", FitJson(m->constant),
      absl::StrFormat(", \"training\": {\"train_n\": %d, \"test_n\": %d, \"train_r\": %.6g, "
                      "\"test_r\": %.6g}", r.train_n, r.test_n, r.train_r, r.test_r),
      ", \"held_out\": ", HeldOutJson(run, *held, names, *m, *base, List(a.held_out)),
      ", \"model\": ", core::JsonQuote(a.out), "}");
}

}  // namespace gaitforge::simtool
