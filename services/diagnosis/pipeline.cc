// The gap finder's stages (pipeline.h), in order.
#include "services/diagnosis/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>

#include <spdlog/spdlog.h>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "robots/controllers.h"
#include "robots/count_override.h"
#include "robots/registry.h"
#include "services/core/file_text.h"
#include "services/core/subprocess.h"
#include "services/diagnosis/locate.h"
#include "services/diagnosis/plan_command.h"
#include "services/diagnosis/run_state.h"
#include "services/recording/recording.h"
#include "workers/effects/effects.h"

namespace gaitforge::diagnosis {
namespace {

std::string ReadFile(const std::string& path) {
  return core::ReadWholeFile(path).value_or("");
}

// The gait period of the command a recording of `robot` holds (its controller kind).
double GaitPeriod(const robots::RobotDescriptor& robot, const recording::Recording& rec) {
  const auto* kind = robots::FindControllerKind(robot.controller.kind);
  return kind && kind->period_s ? kind->period_s(rec.meta.genes) : 1.0;
}

// The compared samples of the training recordings: period bins (or samples, for the
// pointwise and acceleration errors, within window_s when set) times compared channels.
absl::Status CountSamples(RunState& s) {
  auto robot = RobotOf(s.d);
  if (!robot.ok()) return robot.status();
  for (const auto& f : s.in.train_files) {
    auto rec = recording::ParseRecording(ReadFile(f), ReadFile(f + ".json"), f, f + ".json", {},
                                         robot->get());
    if (!rec.ok()) return rec.status();
    const bool per_sample = s.d.error() == "pointwise" || s.d.error() == "acceleration";
    int64_t bins = per_sample ? static_cast<int64_t>(rec->t.size())
                              : std::max<int64_t>(1, std::llround(GaitPeriod(**robot, *rec) / rec->dt));
    if (per_sample && s.d.params().count("window_s") && s.d.params().at("window_s") > 0)
      bins = std::min<int64_t>(bins, std::llround(s.d.params().at("window_s") / rec->dt) + 1);
    int64_t channels = 0;
    const std::vector<std::string> model = (*robot)->Channels();
    const std::vector<std::string> chosen = absl::StrSplit(s.d.channels(), ',', absl::SkipEmpty());
    for (const std::string& c : rec->channels)
      channels += std::find(model.begin(), model.end(), c) != model.end() &&
                  (chosen.empty() || std::find(chosen.begin(), chosen.end(), c) != chosen.end());
    s.n += bins * std::max<int64_t>(1, channels);
  }
  return absl::OkStatus();
}

// Recording weights (weighting: floor or pooled), the same in every fit.
absl::Status Weigh(RunState& s) {
  s.fit_inputs = StudyInputs{s.in.train, s.in.held, ""};
  if (!FloorsMeasured(s.d)) return absl::OkStatus();
  s.weights = FloorWeights(s.d, s.in.train_files, &s.train_floors, &s.variant_train);
  if (s.weights.empty())
    return absl::FailedPreconditionError(
        "weighting: " + s.d.weighting() +
        ": the model failed on a training recording under a numeric variant "
        "(gaitforge-sim calibration-eval)");
  std::vector<std::string> parts;
  for (double w : s.weights) parts.push_back(absl::StrFormat("%.6g", w));
  s.fit_inputs.weights = absl::StrJoin(parts, ",");
  return absl::OkStatus();
}

// 0. Numerics first (numerics: first): while a finer step among the numeric variants
// brings the uncalibrated model closer to the training recordings by more than a fifth,
// the diagnosis moves to that step (its variants with it), so that the model's own step
// error cannot pass for an effect (docs/diagnosis.md, "Numerics first").
absl::Status Numerics(RunState& s) {
  if (s.d.numerics() != "first" || !FloorsMeasured(s.d)) return absl::OkStatus();
  auto robot = RobotOf(s.d);
  const robots::Parameter* h = robot.ok() ? (*robot)->FindParameter(kTimestepParam) : nullptr;
  if (h == nullptr) return absl::OkStatus();
  s.numerics_from_ms = s.d.has_timestep_ms() ? s.d.timestep_ms() : 1e3 * h->value;
  s.numerics_from_error = s.variant_train.empty() ? NAN : s.variant_train[0];
  for (int round = 0; round < 2; ++round) {
    const double own = s.d.has_timestep_ms() ? s.d.timestep_ms() : 1e3 * h->value;
    const double finer = FinerStepMs(NumericVariants(s.d), s.variant_train, own);
    if (finer <= 0 || finer < 0.05) break;
    s.d.set_timestep_ms(finer);
    s.r.note(absl::StrFormat("numerics first: the model's %.3g ms step misses the training "
                             "recordings by %.3g %s, %.3g ms by less: diagnosing at %.3g ms",
                             own, s.rule.error_scale * s.variant_train[0], s.rule.error_unit,
                             finer, finer));
    if (auto st = Weigh(s); !st.ok()) return st;
  }
  return absl::OkStatus();
}

// The structure stages run (structure: first or joint).
bool StructureOn(const v1::DiagnosisSpec& d) {
  return d.structure() == "first" || d.structure() == "joint";
}

// 0b. Resolution (structure: first; robots with counts, such as the arm's lumps): while
// twice a count, within its range, brings the uncalibrated model closer to the training
// recordings by more than a fifth (the rule of numerics first), the diagnosis moves to that
// model: a lumped model coarser than the robot must not pass its own discretisation error
// off as an effect (docs/diagnosis.md, "Structure first").
absl::Status Resolution(RunState& s) {
  if (!StructureOn(s.d) || !FloorsMeasured(s.d) || s.variant_train.empty())
    return absl::OkStatus();
  auto robot = RobotOf(s.d);
  if (!robot.ok()) return absl::OkStatus();
  for (const auto& count : (*robot)->counts) {
    for (int at = count.value; 2 * at <= count.hi; at *= 2) {
      const std::string text = s.d.robot_descriptor().empty()
                                   ? std::string(robots::BuiltinText(s.d.robot()))
                                   : s.d.robot_descriptor();
      auto finer = robots::WithCount(text, count.name, 2 * at,
                                     absl::StrCat(s.d.robot(), " (", count.name, " = ", 2 * at, ")"));
      if (!finer.ok()) break;
      const v1::DiagnosisSpec d = s.d;
      const StudyInputs inputs = s.fit_inputs;
      const auto weights = s.weights, floors = s.train_floors, variants = s.variant_train;
      s.d.set_robot_descriptor(*finer);
      if (!Weigh(s).ok() || !(s.variant_train[0] < kUnconvergedShare * variants[0])) {
        s.d = d;
        s.fit_inputs = inputs;
        s.weights = weights;
        s.train_floors = floors;
        s.variant_train = variants;
        break;
      }
      s.resolution.push_back({count.name, at, 2 * at, variants[0], s.variant_train[0]});
      s.r.note(absl::StrFormat("resolution: with %s = %d the uncalibrated model misses the training "
                               "recordings by %.3g %s, with %d by %.3g %s: diagnosing at %d",
                               count.name, at, s.rule.error_scale * variants[0], s.rule.error_unit,
                               2 * at, s.rule.error_scale * s.variant_train[0], s.rule.error_unit,
                               2 * at));
    }
  }
  return absl::OkStatus();
}

// The baseline's held-out errors, its noise floor and where its residuals show the
// mismatch, on the training recordings and on the held-out ones (if not there, they
// cannot confirm).
void ScoreBase(RunState& s) {
  s.base.bic = s.Bic(s.base);
  ScoreHeldOut(s.base, s.in.held_files, s.d, s.in.dir + "/baseline-held");  // kept: located
  s.floor_sd = SampleSd(s.base.held_variants);
  s.located = Locate(VariantErrors(s.base, s.in.train_files, s.d, s.in.dir + "/baseline-train"),
                     s.in.dir, "baseline-train", "located.json", "located.svg", s.r.note);
  s.located_held =
      Locate(s.base.held_variants, s.in.dir, "baseline-held", "located-held.json", "", s.r.note);
}

// 1. The baseline, and 2. where it misses.
absl::Status Baseline(RunState& s) {
  s.base = Make(s.d, {});
  std::vector<Candidate*> one = {&s.base};
  if (auto st = RunFits(s.studies, s.d, one, s.d.full_evaluations(), s.fit_inputs, s.r,
                        "baseline", &s.reused);
      !st.ok())
    return st;
  if (!s.base.ok) return absl::FailedPreconditionError("the baseline fit failed: " + s.base.reason);
  ScoreBase(s);
  return absl::OkStatus();
}

// With structure first, every fit after the baseline starts from a fit already made: the
// baseline's (its effects at their nominal values: the baseline model itself), or for a
// full fit of one effect, that effect's screening fit; with a shorter first step. Effects
// are sought on top of the fitted model. A screening fit (`hold`) keeps the base
// parameters within 2% of the baseline's values: its short budget goes to the effect's own
// parameters, so that screening ranks what each effect adds to the fitted model rather
// than how far a short fit gets from the centre of every range.
void StartFrom(const RunState& s, const Candidate& from, Candidate& c, bool hold) {
  if (StructureOn(s.d) && from.ok) StartAt(from, &c, hold);
}

// A short fit of each effect in `ids` alone on the base model (screening_evaluations, from
// the baseline's fit when structure is on), all at once; appended to `out` (stage: the
// progress label).
absl::Status ScreenEach(RunState& s, const std::vector<std::string>& ids,
                        const std::string& stage, std::vector<Candidate>* out) {
  const size_t first = out->size();
  for (const auto& id : ids) out->push_back(Make(s.d, {id}));
  std::vector<Candidate*> ptrs;
  for (size_t i = first; i < out->size(); ++i) {
    StartFrom(s, s.base, (*out)[i], true);
    ptrs.push_back(&(*out)[i]);
  }
  return RunFits(s.studies, s.d, ptrs, s.d.screening_evaluations(), s.fit_inputs, s.r, stage,
                 &s.reused);
}

// The structural candidates screened one by one, the lead refitted fully (structure:
// first); every one of them together in one full fit (structure: joint). Not ok: none.
absl::StatusOr<Candidate> FitStructure(RunState& s, const std::vector<std::string>& ids) {
  std::vector<std::string> lead_ids = ids;
  if (s.d.structure() == "first") {
    std::vector<Candidate> tried;
    if (auto st = ScreenEach(s, ids, "structure", &tried); !st.ok()) return st;
    const Candidate* lead = nullptr;
    for (const auto& c : tried)
      if (c.ok && (!lead || c.train < lead->train)) lead = &c;
    if (!lead) return Candidate{};
    lead_ids = lead->effects;
  }
  Candidate best = Make(s.d, lead_ids);
  StartFrom(s, s.base, best, false);
  std::vector<Candidate*> one = {&best};
  if (auto st = RunFits(s.studies, s.d, one, s.d.full_evaluations(), s.fit_inputs, s.r,
                        "structure", &s.reused);
      !st.ok())
    return st;
  return best;
}

// 2b. Structure first (structure: first or joint): the candidates that say what the model
// gets wrong everywhere (effects::IsStructural) are fitted (FitStructure), and if the fit
// beats the baseline as a discovery must (first; decision.h) or as a correction of the
// model's own idealisations may (joint: StructureAdmits) it becomes the baseline: its
// parameters join the base parameters of every later fit and its effects leave the
// candidates, so that the effects compete for what remains instead of with the structure.
absl::Status Structure(RunState& s) {
  if (!StructureOn(s.d)) return absl::OkStatus();
  std::vector<std::string> ids;
  for (const auto& id : s.d.candidates())
    if (effects::IsStructural(id)) ids.push_back(id);
  if (ids.empty()) return absl::OkStatus();
  auto fitted = FitStructure(s, ids);
  if (!fitted.ok()) return fitted.status();
  Candidate best = *std::move(fitted);
  if (!best.ok) return absl::OkStatus();
  best.bic = s.Bic(best);
  ScoreHeldOut(best, s.in.held_files, s.d);
  s.rule.margin = s.d.margin();
  s.rule.held_floor = s.floor_sd;
  const bool joins = s.d.structure() == "joint" ? StructureAdmits(s.base, best, s.rule)
                                                : BeatsBaseline(s.base, best, s.rule);
  if (!joins) {
    s.r.note("structure: none required (the best, " + best.label + ", does not beat the baseline)");
    return absl::OkStatus();
  }
  s.r.note("structure: " + best.label + " joins the baseline");
  s.bic_before_structure = s.base.bic;
  s.structure = best;
  s.d = WithStructure(s.d, best);
  s.base = best;
  s.base.effects.clear();
  s.base.gene_effect.assign(s.base.genes.size(), "");
  s.base.label = "baseline";
  ScoreBase(s);
  return absl::OkStatus();
}

// 3. Screening: every candidate effect, a short fit each, all at once.
absl::Status Screen(RunState& s) {
  const std::vector<std::string> ids(s.d.candidates().begin(), s.d.candidates().end());
  if (auto st = ScreenEach(s, ids, "screening", &s.screened); !st.ok()) return st;
  std::sort(s.screened.begin(), s.screened.end(), [](const Candidate& a, const Candidate& b) {
    if (a.ok != b.ok) return a.ok;
    return a.train < b.train;
  });
  return absl::OkStatus();
}

// Where a pair starts: StartAtBetter (fits.h); with both singles failed, from the baseline
// as a single starts.
void StartPair(const RunState& s, const Candidate& a, const Candidate& b, Candidate& pair) {
  if (!StartAtBetter(a, b, &pair)) StartFrom(s, s.base, pair, false);
}

// 4a. Full fits of the leaders (with screening_tie > 0, near ties with the last leader
// too), all at once.
absl::Status RefitSingles(RunState& s) {
  std::vector<double> screened_train;
  for (const auto& c : s.screened)
    if (c.ok) screened_train.push_back(c.train);
  const int leaders = LeadersToRefit(screened_train, s.d.top(), s.d.screening_tie());
  for (int i = 0; i < leaders; ++i) s.full.push_back(Make(s.d, s.screened[i].effects));
  s.singles = s.full.size();
  std::vector<Candidate*> ptrs;
  for (size_t i = 0; i < s.singles; ++i) {
    StartFrom(s, s.screened[i], s.full[i], false);
    ptrs.push_back(&s.full[i]);
  }
  return RunFits(s.studies, s.d, ptrs, s.d.full_evaluations(), s.fit_inputs, s.r, "refitting",
                 &s.reused);
}

// 4b. Pairs of the first three leaders, once their single fits are done (StartPair).
absl::Status RefitPairs(RunState& s) {
  if (!s.d.try_pairs()) return absl::OkStatus();
  std::vector<std::pair<size_t, size_t>> of;
  for (size_t i = 0; i < s.singles && i < 2; ++i)
    for (size_t j = i + 1; j < s.singles && j < 3; ++j) of.emplace_back(i, j);
  if (of.empty()) return absl::OkStatus();
  s.full.reserve(s.singles + of.size());  // the pointers below stay valid
  std::vector<Candidate*> ptrs;
  for (const auto& [i, j] : of) {
    s.full.push_back(Make(s.d, {s.full[i].effects[0], s.full[j].effects[0]}));
    StartPair(s, s.full[i], s.full[j], s.full.back());
  }
  for (size_t k = s.singles; k < s.full.size(); ++k) ptrs.push_back(&s.full[k]);
  return RunFits(s.studies, s.d, ptrs, s.d.pair_evaluations(), s.fit_inputs, s.r,
                 "refitting pairs", &s.reused);
}

// 4. The leaders' full fits, then their pairs; each scored held out and checked for
// parameters at a bound.
absl::Status Refit(RunState& s) {
  if (auto st = RefitSingles(s); !st.ok()) return st;
  if (auto st = RefitPairs(s); !st.ok()) return st;
  const size_t base_genes = s.d.base_parameters_size();
  for (auto& c : s.full) {
    if (!c.ok) continue;
    c.bic = s.Bic(c);
    ScoreHeldOut(c, s.in.held_files, s.d);
    for (size_t i = base_genes; i < c.genes.size() && i < c.values.size(); ++i) {
      if (c.genes[i].name().rfind("nuisance.", 0) == 0) continue;
      if (AtBound(c.values[i], c.genes[i].lo(), c.genes[i].hi())) {
        c.at_bound = true;
        c.bound_params.push_back(c.genes[i].name());
      }
    }
  }
  std::sort(s.full.begin(), s.full.end(), [](const Candidate& a, const Candidate& b) {
    if (a.ok != b.ok) return a.ok;
    return a.bic < b.bic;
  });
  return absl::OkStatus();
}

// The range of c's parameters that the training data cannot tell from its fit, given the
// model's own spread (range.h), computed when first needed, and what it says of c.
const RangeVerdict& Judge(RunState& s, const Candidate* c) {
  if (s.judged.count(c)) return s.judged[c];
  if (s.ranges.empty()) {
    if (s.train_floors.empty())
      (void)FloorWeights(s.d, s.in.train_files, &s.train_floors, &s.variant_train);
    s.tolerance = TrainingTolerance(s.weights, s.train_floors);
  }
  uint64_t seed = s.d.seed() ^ 0xcbf29ce484222325ull;  // FNV-1a of the label into the seed
  for (unsigned char ch : c->label) seed = (seed ^ ch) * 0x100000001b3ull;
  const auto started = std::chrono::steady_clock::now();
  s.ranges[c] = FloorRange(*c, s.d, s.in.train_files, s.weights, s.tolerance, seed);
  s.r.note(absl::StrFormat(
      "range: %s: %d evaluations, %d within %.3g %s of the least (%.0f s)", c->label,
      s.ranges[c].evaluations, s.ranges[c].accepted, s.rule.error_scale * s.tolerance,
      s.rule.error_unit,
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count()));
  return s.judged[c] = JudgeRange(*c, s.ranges[c], s.d.base_parameters_size());
}

// 5. Decide: a first named fit whose effects the data do not require is set aside
// (DecideRequired); a rival they do not require or pin is no rival (PreferDetermined).
void DecideStage(RunState& s) {
  s.rule.margin = s.d.margin();
  s.rule.held_floor = s.floor_sd;
  s.rule.train_floor = SampleSd(s.variant_train);
  s.rule.finest_step = FinestStepVariant(NumericVariants(s.d));
  s.decision = DecideRequired(
      s.base, std::vector<FitScore>(s.full.begin(), s.full.end()), s.rule,
      [&](int i) { return Judge(s, &s.full[i]).unneeded_effects; }, &s.set_aside);
  std::vector<bool> weak;
  for (int i : s.decision.named) {
    const RangeVerdict& v = Judge(s, &s.full[i]);
    weak.push_back(!v.loose.empty() || !v.unneeded.empty());
  }
  s.decision = PreferDetermined(s.decision, weak, &s.dropped);
  for (int i : s.decision.named) s.named.push_back(&s.full[i]);
  if (s.decision.remainder_of >= 0) s.source = &s.full[s.decision.remainder_of];
  for (int i : s.set_aside)
    s.r.note("not required: " + s.full[i].label + " (" + s.judged[&s.full[i]].unneeded + ")");
  for (int i : s.dropped) s.r.note("not a rival: " + s.full[i].label);
}

// 6. The corrected model: the robot's gait objective with the named fit's values, ready
// for new gait studies.
void WriteCorrected(RunState& s) {
  if (s.named.empty()) return;
  std::vector<std::string> set;
  const Candidate& w = *s.named[0];
  for (size_t i = 0; i < w.genes.size(); ++i)
    if (w.genes[i].name().rfind("nuisance.", 0) != 0)
      set.push_back(absl::StrFormat("%s=%.9g", w.genes[i].name(), w.values[i]));
  s.corrected = s.in.dir + "/corrected-model.yaml";
  std::ofstream out(s.corrected);
  out << "# The " << s.d.robot() << " model with the effect the gap finder found (" << w.label
      << "),\n# ready for new gait studies: use this objective section in a study spec.\n";
  if (s.d.robot_descriptor().empty()) {
    out << "objective:\n  name: " << s.d.robot() << ".distance\n";
  } else {
    // The robot's descriptor beside it; the study spec names it relative to itself.
    std::ofstream(s.in.dir + "/robot.yaml", std::ios::binary) << s.d.robot_descriptor();
    out << "objective:\n  name: robot.distance\n  robot: robot.yaml  # beside this file\n";
  }
  out << "  options:\n    set: \"" << absl::StrJoin(set, ",") << "\"\n";
}

// When the recordings left explanations undecided, or nothing explained the held-out
// mismatch, or the effect named is parted from the baseline by no recording given by the
// decisive level (plan.h, WhyPlan), the recordings that would decide them, kept as
// dir/plan.json: gaitforge-sim plan on the diagnosis's own model (its descriptor and step as
// it ran) and recordings. A plan that fails is a note, not a failure.
void PlanStage(RunState& s, const std::string& report) {
  const plan::PlanReason why = plan::WhyPlan(report);
  if (why == plan::PlanReason::kNone) return;
  s.r.progress({"plan", 0, 0, 1, "planning the recordings that would decide"});
  std::vector<std::string> files = s.in.train_files;
  files.insert(files.end(), s.in.held_files.begin(), s.in.held_files.end());
  plan::Options o;
  o.report = s.in.dir + "/diagnosis.json";
  o.threads = 2;
  std::string json;
  if (core::RunCapture(PlanCommand(s.d, RobotArg(s.d), files, o, {}), &json) != 0) {
    // A named effect stands without a plan; a failed plan only matters where one was owed.
    if (why != plan::PlanReason::kConfirm)
      s.r.note("warning: no plan of the recordings that would decide (gaitforge-sim plan failed)");
    return;
  }
  double decisive = NAN;
  const double given = plan::RecordedSeparation(json, plan::FirstNamed(report), &decisive);
  if (why == plan::PlanReason::kConfirm && given >= decisive) return;  // the data decided it
  std::ofstream(s.in.dir + "/plan.json") << json;
}

}  // namespace

absl::StatusOr<std::string> Diagnose(const v1::DiagnosisSpec& d, const Inputs& in,
                                     Studies& studies, const Reporter& r) {
  std::error_code ec;
  std::filesystem::create_directories(in.dir, ec);
  RunState s(d, in, studies, r);
  s.rule.SetUnitFor(d.error());
  using Stage = absl::Status (*)(RunState&);
  const std::pair<const char*, Stage> stages[] = {
      {"samples", CountSamples}, {"weights", Weigh},   {"numerics", Numerics},
      {"resolution", Resolution}, {"baseline", Baseline}, {"structure", Structure},
      {"screening", Screen},      {"refit", Refit}};
  for (const auto& [name, stage] : stages) {
    const auto t0 = std::chrono::steady_clock::now();
    if (auto st = stage(s); !st.ok()) return st;
    // Wall time goes to the log, not the report: the report depends on the spec alone.
    spdlog::info("diagnosis {}: {} took {:.1f} s", d.name(), name,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  DecideStage(s);
  WriteCorrected(s);
  std::string report = WriteReport(s);
  const auto t0 = std::chrono::steady_clock::now();
  PlanStage(s, report);
  spdlog::info("diagnosis {}: plan took {:.1f} s", d.name(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return report;
}

}  // namespace gaitforge::diagnosis
