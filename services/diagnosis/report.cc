// The gap finder's report (docs/diagnosis.md, "The report"): diagnosis.json, the overlays
// of the baseline and the named explanation on the held-out recordings, and its figures.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "services/core/subprocess.h"
#include "services/core/json_text.h"
#include "services/diagnosis/locate.h"
#include "services/diagnosis/run_state.h"
#include "workers/effects/effects.h"

namespace gaitforge::diagnosis {
namespace {

using core::JsonQuote;
const auto& Num = core::JsonNum;
const auto& NumList = core::JsonNumList;
const auto& StringList = core::JsonStringList;

bool Has(const std::vector<int>& v, int i) { return std::find(v.begin(), v.end(), i) != v.end(); }

// Why c was not named, in words (decision.h WhyNotNamed, and the range rules' reasons).
std::string WhyNot(const RunState& s, const Candidate& c) {
  const int i = static_cast<int>(&c - s.full.data());
  if (Has(s.set_aside, i))
    return absl::StrFormat(
        "passed every test, but the data do not require it: the model without the effect "
        "fits the training data within their own spread of the fit (%s)",
        s.judged.at(&c).unneeded);
  if (Has(s.dropped, i)) {
    const RangeVerdict& v = s.judged.at(&c);
    return absl::StrFormat(
        "a rival of %s within the decision's margins, but the training data %s: it absorbs "
        "the mismatch rather than measures an effect",
        s.named[0]->label,
        !v.unneeded.empty() ? "do not require it (" + v.unneeded + ")"
                            : "do not pin its magnitudes: " + v.loose +
                                  " of the allowed values fit within the model's own spread");
  }
  if (s.source && BeatsBaseline(s.base, c, s.rule) && c.held < s.named[0]->held)
    return absl::StrFormat(
        "passed every test and predicts the held-out recordings better than the named "
        "explanation (%.3g against %.3g %s), but of %s (held out %.3g %s, set aside) the "
        "data require only %s, which is named for it",
        s.rule.error_scale * c.held, s.rule.error_scale * s.named[0]->held, s.rule.error_unit,
        s.source->label, s.rule.error_scale * s.source->held, s.rule.error_unit,
        s.named[0]->label);
  std::vector<const FitScore*> others;
  for (const Candidate& f : s.full) others.push_back(&f);
  return WhyNotNamed(s.base, c, s.named.empty() ? nullptr : s.named[0], s.rule, others);
}

std::string Params(const RunState& s, const Candidate& c) {
  std::string j = "{";
  const auto range = s.ranges.find(&c);
  for (size_t i = 0; i < c.genes.size() && i < c.values.size(); ++i) {
    absl::StrAppend(&j, i ? ", " : "", JsonQuote(c.genes[i].name()), ": {\"index\": ", i,
                    ", \"value\": ", Num(c.values[i]), ", \"sd\": ", i < c.spread.size() ? Num(c.spread[i]) : "null",
                    ", \"lo\": ", Num(c.genes[i].lo()), ", \"hi\": ", Num(c.genes[i].hi()));
    if (range != s.ranges.end() && std::isfinite(range->second.tolerance) &&
        i < range->second.params.size() && c.genes[i].name().rfind("nuisance.", 0) != 0) {
      const ParamRange& r = range->second.params[i];
      absl::StrAppend(&j, ", \"range\": [", Num(r.lo), ", ", Num(r.hi), "], \"range_share\": ",
                      Num(RangeShare(r, c.genes[i].lo(), c.genes[i].hi())));
    }
    absl::StrAppend(&j, "}");
  }
  return j + "}";
}

// The effects' names and meanings, from the catalog or the robot's own suspects.
std::vector<effects::EffectInfo> Infos(const RunState& s, const Candidate& c) {
  std::vector<effects::EffectInfo> out;
  auto robot = RobotOf(s.d);
  if (!robot.ok()) return out;
  for (const std::string& id : c.effects)
    if (auto e = effects::FindEffect(id, **robot)) out.push_back(std::move(*e));
  return out;
}

std::string Effect(const RunState& s, const Candidate& c) {
  std::vector<std::string> names, meanings;
  for (const auto& e : Infos(s, c)) {
    names.push_back(e.name);
    meanings.push_back(e.meaning);
  }
  // The parts that correct the model's own idealisations (effects::IsStructural) rather
  // than name physics it left out.
  std::vector<std::string> structural;
  for (const std::string& id : c.effects)
    if (effects::IsStructural(id)) structural.push_back(id);
  std::string j = absl::StrCat("{\"id\": ", JsonQuote(c.label), ", \"name\": ",
                               JsonQuote(absl::StrJoin(names, " + ")), ", \"meaning\": ",
                               JsonQuote(absl::StrJoin(meanings, " ")),
                               ", \"structural\": ", StringList(structural),
                               ", \"params\": ", Params(s, c));
  if (const auto range = s.ranges.find(&c); range != s.ranges.end())
    absl::StrAppend(&j, ", \"range_tolerance\": ", Num(range->second.tolerance),
                    ", \"range_evaluations\": ", range->second.evaluations,
                    ", \"range_accepted\": ", range->second.accepted);
  absl::StrAppend(&j, ", \"train\": ", Num(c.train), ", \"held_out\": ", Num(c.held),
                  ", \"held_out_variants\": ", NumList(c.held_variants),
                  ", \"paired_t\": ", Num(PairedT(s.base.held_variants, c.held_variants)),
                  ", \"at_bound\": ", StringList(c.bound_params),
                  ", \"delta_bic\": ", Num(c.bic - s.base.bic), ", \"study_id\": ",
                  JsonQuote(c.study_id));
  if (std::find(s.named.begin(), s.named.end(), &c) == s.named.end())
    absl::StrAppend(&j, ", \"why_not\": ", JsonQuote(WhyNot(s, c)));
  return j + "}";
}

// The structure that joined the baseline (structure: first), or null: what the model got
// wrong everywhere, reported beside the effects found on top of it.
std::string Structure(const RunState& s) {
  const Candidate& c = s.structure;
  if (c.effects.empty()) return "null";
  std::vector<std::string> names, meanings;
  for (const auto& e : Infos(s, c)) {
    names.push_back(e.name);
    meanings.push_back(e.meaning);
  }
  return absl::StrCat("{\"id\": ", JsonQuote(c.label), ", \"name\": ",
                      JsonQuote(absl::StrJoin(names, " + ")), ", \"meaning\": ",
                      JsonQuote(absl::StrJoin(meanings, " ")), ", \"params\": ", Params(s, c),
                      ", \"train\": ", Num(c.train), ", \"held_out\": ", Num(c.held),
                      ", \"delta_bic\": ", Num(c.bic - s.bic_before_structure),
                      ", \"study_id\": ", JsonQuote(c.study_id), "}");
}

// The step the diagnosis ran at when numerics first moved it (numerics: first), or null.
std::string Numerics(const RunState& s) {
  if (!std::isfinite(s.numerics_from_ms) || !s.d.has_timestep_ms() ||
      s.d.timestep_ms() == s.numerics_from_ms)
    return "null";
  return absl::StrCat("{\"from_ms\": ", Num(s.numerics_from_ms), ", \"at_ms\": ",
                      Num(s.d.timestep_ms()), ", \"from_training_error\": ",
                      Num(s.numerics_from_error), ", \"at_training_error\": ",
                      Num(s.variant_train.empty() ? NAN : s.variant_train[0]), "}");
}

// The counts the diagnosis moved to (structure: first), or null when none moved.
std::string Resolution(const RunState& s) {
  if (s.resolution.empty()) return "null";
  std::vector<std::string> moves;
  for (const auto& m : s.resolution)
    moves.push_back(absl::StrCat("{\"count\": ", JsonQuote(m.count), ", \"from\": ", m.from,
                                 ", \"at\": ", m.at, ", \"from_training_error\": ",
                                 Num(m.from_error), ", \"at_training_error\": ", Num(m.at_error),
                                 "}"));
  return "[" + absl::StrJoin(moves, ", ") + "]";
}

std::string Errors(const RunState& s) {
  std::string j = absl::StrCat(
      "{\"baseline_train\": ", Num(s.base.train), ", \"baseline_held_out\": ", Num(s.base.held),
      ", \"baseline_held_out_variants\": ", NumList(s.base.held_variants),
      ", \"noise_floor_held_out\": ", Num(s.floor_sd), ", \"weighting\": ",
      JsonQuote(s.d.weighting()), ", \"training_weights\": ", NumList(s.weights),
      ", \"training_floors\": ", NumList(s.train_floors), ", \"variant_training_errors\": ",
      NumList(s.variant_train));
  if (!s.named.empty())
    absl::StrAppend(&j, ", \"train\": ", Num(s.named[0]->train), ", \"held_out\": ",
                    Num(s.named[0]->held));
  return j + "}";
}

// The figure's overlays: the baseline and the named explanation (or, with none named, the
// fit closest held out) simulated on the held-out recordings.
std::string Overlay(const RunState& s, const Candidate* shown) {
  std::string j = "{\"baseline_eval\": ";
  if (std::isfinite(s.base.held_variants[0]))  // evaluated into baseline-held by ScoreHeldOut
    absl::StrAppend(&j, JsonQuote(s.in.dir + "/baseline-held/eval.json"));
  else
    absl::StrAppend(&j, "null");
  if (shown &&
      std::isfinite(HeldOutError(*shown, s.in.held_files, s.d, s.in.dir + "/explanation-held")))
    absl::StrAppend(&j, ", \"other_eval\": ", JsonQuote(s.in.dir + "/explanation-held/eval.json"),
                    ", \"other\": ",
                    JsonQuote(s.named.empty() ? "closest rejected: " + shown->label
                                              : shown->label));
  return j + "}";
}

std::string Experiment(const RunState& s, const NoneReading& none) {
  if (!none.experiment.empty()) return none.experiment;
  std::string e;
  if (s.decision.verdict == "ambiguous")
    for (const auto* c : s.named) {
      const auto infos = Infos(s, *c);
      if (!infos.empty()) e += infos[0].experiment + " ";
    }
  return e;
}

}  // namespace

std::string WriteReport(RunState& s) {
  const Candidate* shown = s.named.empty() ? nullptr : s.named[0];
  if (!shown)
    for (const auto& c : s.full)
      if (c.ok && std::isfinite(c.held) && (!shown || c.held < shown->held)) shown = &c;
  const SpreadReading spread = ReadSpread(s.located, s.located_held);
  const NoneReading none = s.decision.verdict == "none"
                               ? ReadNone(spread, s.in.held_files, shown ? shown->label : "")
                               : NoneReading{};
  std::vector<std::string> named, runners, screened;
  for (const auto* c : s.named) named.push_back(Effect(s, *c));
  for (const auto& c : s.full)
    if (s.named.empty() || &c != s.named[0]) runners.push_back(Effect(s, c));
  for (const auto& c : s.screened)
    screened.push_back(absl::StrCat("{\"id\": ", JsonQuote(c.label), ", \"train\": ",
                                    Num(c.train), ", \"study_id\": ", JsonQuote(c.study_id), "}"));
  std::string json = absl::StrCat(
      "{\"name\": ", JsonQuote(s.d.name()), ", \"robot\": ", JsonQuote(s.d.robot()),
      ", \"verdict\": ", JsonQuote(s.decision.verdict), ", \"effects\": [",
      absl::StrJoin(named, ", "), "], \"errors\": ", Errors(s), ", \"runners_up\": [",
      absl::StrJoin(runners, ", "), "], \"screening\": [", absl::StrJoin(screened, ", "),
      "], \"top\": ", s.d.top(), ", \"screening_tie\": ", Num(s.d.screening_tie()),
      ", \"refitted_singles\": ", s.singles, ", \"reused_fits\": ", s.reused,
      ", \"baseline_study_id\": ", JsonQuote(s.base.study_id), ", \"baseline\": {\"params\": ",
      Params(s, s.base), ", \"train\": ", Num(s.base.train), ", \"held_out\": ", Num(s.base.held),
      "}, \"structure\": ", Structure(s),
      ", \"numerics\": ", Numerics(s), ", \"resolution\": ", Resolution(s));
  absl::StrAppend(&json, ", \"unexplained_mismatch\": ", none.unexplained ? "true" : "false",
                  ", \"none_reading\": ", JsonQuote(none.words), ", \"numerics_note\": ",
                  JsonQuote(NumericsNote(NumericVariants(s.d), s.variant_train, s.rule)),
                  ", \"located\": ", s.located,
                  ", \"located_held_out\": ", s.located_held, ", \"experiment\": ",
                  JsonQuote(Experiment(s, none)), ", \"corrected_model\": ",
                  JsonQuote(s.corrected), ", \"compared_samples\": ", s.n,
                  ", \"rule\": {\"error_scale\": ", Num(s.rule.error_scale),
                  ", \"error_unit\": ", JsonQuote(s.rule.error_unit),
                  ", \"margin\": ", Num(s.rule.margin), ", \"held_out_gain\": ",
                  Num(s.rule.held_out_gain), ", \"paired_t\": ", Num(s.rule.paired_t),
                  ", \"pair_gain\": ", Num(s.rule.pair_gain),
                  ", \"finest_step_variant\": ", s.rule.finest_step, "}, \"overlay\": ",
                  Overlay(s, shown), ", \"dir\": ", JsonQuote(s.in.dir));
  // The figures: drawn from the report itself, then listed in it (only those written).
  const std::string path = s.in.dir + "/diagnosis.json";
  std::ofstream(path) << json << "}\n";
  std::vector<std::string> figures;
  if (std::filesystem::exists(s.in.dir + "/located.svg")) figures.push_back(s.in.dir + "/located.svg");
  std::string ignored;
  if (core::RunCapture({core::Python(), core::PythonScript("gaitforge_plot.py"), "diagnosis",
                        "--report", path, "--out", s.in.dir + "/diagnosis.svg"},
                       &ignored) == 0)
    figures.push_back(s.in.dir + "/diagnosis.svg");
  else
    s.r.note("warning: the diagnosis figure could not be drawn "
             "(clients/python/gaitforge_plot.py diagnosis; needs python3-matplotlib)");
  absl::StrAppend(&json, ", \"figures\": ", StringList(figures), "}\n");
  std::ofstream(path) << json;
  return json;
}

}  // namespace gaitforge::diagnosis
