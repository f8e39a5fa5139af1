// `gaitforge diagnose SPEC`: the gap finder (docs/diagnosis.md). A study of calibration
// studies run on the coordinator and its workers:
//   1. baseline: calibrate the base model (its uncertain parameters and the time offset;
//      marker offsets are profiled out), every fit weighting the training recordings by
//      their noise floors (weighting: floor, FloorWeights) or equally;
//   2. locate: slice the baseline's residuals on the training and the held-out recordings
//      against the model's own spread under the numeric variants (diagnosis_locate.h,
//      clients/python/gaitforge_locate.py);
//   3. screen every candidate effect (workers/effects) with a short fit, all at once;
//   4. refit the leading candidates fully, and pairs of them;
//   5. decide by BIC on the training error and by the held-out error over an ensemble of
//      numerically irrelevant variants (timestep, contact softness): "found" only when an
//      effect beats the baseline by the BIC margin AND cuts the ensemble-mean held-out
//      error by 15% AND wins the paired comparison across the variants (one-sided t test,
//      5%); of those that pass, the lowest held-out error is named; two effects within the
//      margin of each other, or a rival the held-out data cannot reject that fits the
//      training data better: "ambiguous", with an experiment that tells them apart; else
//      "none" (clients/cli/diagnosis_decision.h), read against the located spread: a match,
//      or a mismatch nothing in the catalog explains, with the recording to add.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <thread>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "clients/cli/cli.h"
#include "clients/cli/diagnosis_decision.h"
#include "clients/cli/diagnosis_fits.h"
#include "clients/cli/diagnosis_locate.h"
#include "clients/cli/diagnosis_range.h"
#include "clients/cli/diagnosis_spec.h"
#include "clients/cli/processes.h"
#include "gaitforge/v1/diagnosis.pb.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"
#include "services/recording/recording.h"
#include "services/spec/spec_loader.h"
#include "workers/effects/effects.h"

namespace gaitforge::cli {

std::string DownloadRecording(Connection& conn, const std::string& hash, const std::string& dir,
                              const GlobalOptions& g);

using namespace diagnosis;  // NOLINT: the gap finder's spec and fits (diagnosis_*.h)

namespace {

std::string Num(double x) { return std::isfinite(x) ? absl::StrFormat("%.6g", x) : "null"; }

std::string NumList(const std::vector<double>& v) {
  std::vector<std::string> parts;
  for (double x : v) parts.push_back(Num(x));
  return "[" + absl::StrJoin(parts, ", ") + "]";
}

}  // namespace

int CmdDiagnose(const GlobalOptions& g, const std::vector<std::string>& args, int workers,
                int threads, const std::string& out_root) {
  if (args.size() != 1) {
    std::cerr << "gaitforge: usage: gaitforge diagnose SPEC.yaml [--workers N] [--json]\n";
    return kUsage;
  }
  std::ifstream in(args[0]);
  if (!in) {
    std::cerr << "gaitforge: cannot open diagnosis spec '" << args[0] << "'\n";
    return kNotFound;
  }
  std::stringstream text;
  text << in.rdbuf();
  v1::DiagnosisSpec d;
  if (auto s = spec::ParseMessage(text.str(), args[0], &d, nullptr); !s.ok()) {
    std::cerr << "gaitforge: " << s.message() << "\n";
    return kUsage;
  }
  Defaults(&d);
  if (auto s = Validate(d); !s.ok()) {
    std::cerr << "gaitforge: " << args[0] << ": " << s.message() << "\n";
    return kUsage;
  }
  int code = kOk;
  auto conn = Connect(g, true, &code);
  if (!conn) return code;
  std::vector<pid_t> pids;
  if (g.coordinator.empty()) pids = StartLocalWorkers(g, conn->target(), workers, threads);
  // Its calibration studies, live (docs/dashboard.md).
  if (!g.json && !conn->dashboard_url().empty())
    std::cerr << "dashboard: " << conn->dashboard_url() << "\n";
  struct Stopper {
    std::vector<pid_t>& p;
    ~Stopper() { for (pid_t x : p) Stop(x, 10); }
  } stopper{pids};

  // Recordings: upload the files, keep the hashes; local copies for evaluation.
  v1::StudySpec carrier;
  for (const auto& r : d.training()) carrier.mutable_objective()->add_recordings(r);
  for (const auto& r : d.held_out()) carrier.mutable_objective()->add_held_out(r);
  if (int c = UploadSpecRecordings(*conn, args[0], &carrier, g); c) return c;
  const std::vector<std::string> train(carrier.objective().recordings().begin(),
                                       carrier.objective().recordings().end());
  const std::vector<std::string> held(carrier.objective().held_out().begin(),
                                      carrier.objective().held_out().end());
  const std::string dir = out_root + "/" + d.name() + "-diagnosis";
  std::error_code ec;
  std::filesystem::create_directories(dir + "/recordings", ec);
  std::vector<std::string> train_files, held_files;
  int64_t n = 0;  // compared samples, for the BIC: period bins x channels per recording
  for (const auto& h : train) {
    const std::string f = DownloadRecording(*conn, h, dir + "/recordings", g);
    if (f.empty()) return kFailed;
    train_files.push_back(f);
    std::ifstream a(f), b(f + ".json");
    std::stringstream sa, sb;
    sa << a.rdbuf();
    sb << b.rdbuf();
    auto rec = recording::ParseRecording(sa.str(), sb.str(), f, f + ".json");
    if (!rec.ok()) {
      std::cerr << "gaitforge: " << rec.status().message() << "\n";
      return kUsage;
    }
    const double period = rec->meta.genes.size() == 13 ? rec->meta.genes[12] : 1.0;
    const int64_t bins = d.error() == "pointwise"
                             ? static_cast<int64_t>(rec->t.size())
                             : std::max<int64_t>(1, std::llround(period / rec->dt));
    n += bins * static_cast<int64_t>(rec->channels.size());
  }
  for (const auto& h : held) {
    const std::string f = DownloadRecording(*conn, h, dir + "/recordings", g);
    if (f.empty()) return kFailed;
    held_files.push_back(f);
  }
  auto bic = [&](const Candidate& c) {
    return static_cast<double>(n) * std::log(std::max(c.train * c.train, 1e-300)) +
           c.k * std::log(static_cast<double>(n));
  };

  // Recording weights (weighting: floor), the same in every fit.
  std::vector<double> weights, train_floors;
  std::string weights_option;
  if (d.weighting() == "floor") {
    weights = FloorWeights(d, train_files, &train_floors);
    if (weights.empty()) {
      std::cerr << "gaitforge: weighting: floor: the model failed on a training recording under "
                   "a numeric variant (gaitforge-sim calibration-eval)\n";
      return kFailed;
    }
    std::vector<std::string> parts;
    for (double w : weights) parts.push_back(absl::StrFormat("%.6g", w));
    weights_option = absl::StrJoin(parts, ",");
  }

  // 1. Baseline.
  int reused = 0;  // fits found in the database with the same spec, not run again
  Candidate base = Make(d, {});
  if (int c = RunStudies(*conn, d, {&base}, d.full_evaluations(), train, held, weights_option, g,
                         "baseline", &reused); c)
    return c;
  if (!base.ok) {
    std::cerr << "gaitforge: the baseline fit failed: " << base.reason << "\n";
    return kFailed;
  }
  base.bic = bic(base);
  // The noise floor: the spread of the baseline's held-out error over the numeric variants.
  ScoreHeldOut(base, held_files, d, dir + "/baseline-held");  // kept: located below
  double floor_sd = 0;
  for (double e : base.held_variants) floor_sd += (e - base.held) * (e - base.held);
  floor_sd = std::sqrt(floor_sd / std::max<size_t>(1, base.held_variants.size() - 1));

  // 2. Locate, on the baseline's residuals: where the training recordings show the
  // mismatch, and whether the held-out ones show it at all (if not, they cannot confirm).
  const std::string located =
      Locate(VariantErrors(base, train_files, d, dir + "/baseline-train"), dir, "baseline-train",
             "located.json", "located.svg");
  const std::string located_held =
      Locate(base.held_variants, dir, "baseline-held", "located-held.json", "");

  // 3. Screening: every candidate effect, a short fit each, all at once.
  std::vector<Candidate> screened;
  for (const auto& id : d.candidates()) screened.push_back(Make(d, {id}));
  std::vector<Candidate*> ptrs;
  for (auto& c : screened) ptrs.push_back(&c);
  if (int c = RunStudies(*conn, d, ptrs, d.screening_evaluations(), train, held, weights_option, g,
                         "screening", &reused); c)
    return c;
  std::sort(screened.begin(), screened.end(), [](const Candidate& a, const Candidate& b) {
    if (a.ok != b.ok) return a.ok;
    return a.train < b.train;
  });

  // 4. Full fits of the leaders, then pairs of them.
  // With screening_tie > 0, near ties with the last leader are refitted too.
  std::vector<double> screened_train;
  for (const auto& c : screened)
    if (c.ok) screened_train.push_back(c.train);
  const int leaders = LeadersToRefit(screened_train, d.top(), d.screening_tie());
  std::vector<Candidate> full;
  for (int i = 0; i < leaders; ++i) full.push_back(Make(d, screened[i].effects));
  const size_t singles = full.size();
  if (d.try_pairs())
    for (size_t i = 0; i < singles && i < 2; ++i)
      for (size_t j = i + 1; j < singles && j < 3; ++j)
        full.push_back(Make(d, {full[i].effects[0], full[j].effects[0]}));
  ptrs.clear();
  for (auto& c : full) ptrs.push_back(&c);
  if (int c = RunStudies(*conn, d, ptrs, d.full_evaluations(), train, held, weights_option, g,
                         "refitting", &reused); c)
    return c;
  const size_t base_genes = d.base_parameters_size();
  for (auto& c : full) {
    if (!c.ok) continue;
    c.bic = bic(c);
    ScoreHeldOut(c, held_files, d);
    for (size_t i = base_genes; i < c.genes.size() && i < c.values.size(); ++i) {
      if (c.genes[i].name().rfind("nuisance.", 0) == 0) continue;
      if (AtBound(c.values[i], c.genes[i].lo(), c.genes[i].hi())) {
        c.at_bound = true;
        c.bound_params.push_back(c.genes[i].name());
      }
    }
  }
  std::sort(full.begin(), full.end(), [](const Candidate& a, const Candidate& b) {
    if (a.ok != b.ok) return a.ok;
    return a.bic < b.bic;
  });

  // 5. Decide (clients/cli/diagnosis_decision.h).
  DecisionRule rule;
  rule.margin = d.margin();
  // Each named fit's parameters come with the range that the training data cannot tell
  // from the fit, given the model's own spread (diagnosis_range.h), computed when first
  // needed; the ranges say whether the data require each named effect and pin it.
  std::map<const Candidate*, FitRange> ranges;
  std::map<const Candidate*, RangeVerdict> judged;
  double tolerance = NAN;
  auto judge = [&](const Candidate* c) -> const RangeVerdict& {
    if (judged.count(c)) return judged[c];
    if (ranges.empty()) {
      if (train_floors.empty()) (void)FloorWeights(d, train_files, &train_floors);
      tolerance = TrainingTolerance(weights, train_floors);
    }
    uint64_t seed = d.seed() ^ 0xcbf29ce484222325ull;  // FNV-1a of the label into the seed
    for (unsigned char ch : c->label) seed = (seed ^ ch) * 0x100000001b3ull;
    if (!g.json) std::cerr << "range: " << c->label << " ..." << std::flush;
    const auto started = std::chrono::steady_clock::now();
    ranges[c] = FloorRange(*c, d, train_files, weights, tolerance, seed);
    if (!g.json)
      std::cerr << absl::StrFormat(
          " %d evaluations, %d within %.3g mm of the least (%.0f s)\n", ranges[c].evaluations,
          ranges[c].accepted, 1000 * tolerance,
          std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count());
    return judged[c] = JudgeRange(*c, ranges[c], base_genes);
  };
  // A first named fit whose effects the data do not require is set aside (DecideRequired);
  // a rival they do not require or pin is no rival (PreferDetermined).
  std::vector<int> set_aside, dropped;
  Decision decision = DecideRequired(
      base, std::vector<FitScore>(full.begin(), full.end()), rule,
      [&](int i) { return judge(&full[i]).unneeded_effects; }, &set_aside);
  std::vector<bool> weak;
  for (int i : decision.named) {
    const RangeVerdict& v = judge(&full[i]);
    weak.push_back(!v.loose.empty() || !v.unneeded.empty());
  }
  decision = PreferDetermined(decision, weak, &dropped);
  std::vector<const Candidate*> named;
  for (int i : decision.named) named.push_back(&full[i]);
  const std::string verdict = decision.verdict;
  const Candidate* source = decision.remainder_of >= 0 ? &full[decision.remainder_of] : nullptr;
  for (int i : set_aside)
    if (!g.json)
      std::cerr << "not required: " << full[i].label << " (" << judged[&full[i]].unneeded
                << ")\n";
  for (int i : dropped)
    if (!g.json) std::cerr << "not a rival: " << full[i].label << "\n";

  // 6. The corrected model: a caterpillar.distance option ready for new gait studies.
  std::string corrected;
  if (!named.empty()) {
    std::vector<std::string> set;
    const Candidate& w = *named[0];
    for (size_t i = 0; i < w.genes.size(); ++i)
      if (w.genes[i].name().rfind("nuisance.", 0) != 0)
        set.push_back(absl::StrFormat("%s=%.9g", w.genes[i].name(), w.values[i]));
    corrected = dir + "/corrected-model.yaml";
    std::ofstream(corrected)
        << "# The caterpillar model with the effect the gap finder found (" << w.label
        << "),\n# ready for new gait studies: use this objective section in a study spec.\n"
        << "objective:\n  name: caterpillar.distance\n  options:\n    set: \""
        << absl::StrJoin(set, ",") << "\"\n";
  }

  // Report: JSON and words.
  auto why_not = [&](const Candidate& c) {
    const int i = static_cast<int>(&c - full.data());
    if (std::find(set_aside.begin(), set_aside.end(), i) != set_aside.end())
      return absl::StrFormat(
          "passed every test, but the data do not require it: the model without the effect "
          "fits the training data within their own spread of the fit (%s)",
          judged[&c].unneeded);
    if (std::find(dropped.begin(), dropped.end(), i) != dropped.end()) {
      const RangeVerdict& v = judged[&c];
      return absl::StrFormat(
          "a rival of %s within the decision's margins, but the training data %s: it absorbs "
          "the mismatch rather than measures an effect",
          named[0]->label,
          !v.unneeded.empty()
              ? "do not require it (" + v.unneeded + ")"
              : "do not pin its magnitudes: " + v.loose +
                    " of the allowed values fit within the model's own spread");
    }
    if (source && BeatsBaseline(base, c, rule) && c.held < named[0]->held)
      return absl::StrFormat(
          "passed every test and predicts the held-out recordings better than the named "
          "explanation (%.3g against %.3g mm), but of %s (held out %.3g mm, set aside) the "
          "data require only %s, which is named for it",
          1000 * c.held, 1000 * named[0]->held, source->label, 1000 * source->held,
          named[0]->label);
    std::vector<const FitScore*> others;
    for (const Candidate& f : full) others.push_back(&f);
    return WhyNotNamed(base, c, named.empty() ? nullptr : named[0], rule, others);
  };
  auto effect_json = [&](const Candidate& c) {
    std::string j = absl::StrCat("{\"id\": ", JsonQuote(c.label), ", \"params\": {");
    const auto range = ranges.find(&c);
    for (size_t i = 0; i < c.genes.size() && i < c.values.size(); ++i) {
      absl::StrAppend(&j, i ? ", " : "", JsonQuote(c.genes[i].name()), ": {\"value\": ",
                      Num(c.values[i]), ", \"sd\": ", i < c.spread.size() ? Num(c.spread[i]) : "null");
      if (range != ranges.end() && std::isfinite(range->second.tolerance) &&
          i < range->second.params.size() && c.genes[i].name().rfind("nuisance.", 0) != 0) {
        const ParamRange& r = range->second.params[i];
        absl::StrAppend(&j, ", \"range\": [", Num(r.lo), ", ", Num(r.hi), "], \"range_share\": ",
                        Num(RangeShare(r, c.genes[i].lo(), c.genes[i].hi())));
      }
      absl::StrAppend(&j, "}");
    }
    absl::StrAppend(&j, "}");
    if (range != ranges.end())
      absl::StrAppend(&j, ", \"range_tolerance\": ", Num(range->second.tolerance),
                      ", \"range_evaluations\": ", range->second.evaluations,
                      ", \"range_accepted\": ", range->second.accepted);
    absl::StrAppend(&j, ", \"train\": ", Num(c.train), ", \"held_out\": ", Num(c.held),
                    ", \"held_out_variants\": ", NumList(c.held_variants),
                    ", \"paired_t\": ", Num(PairedT(base.held_variants, c.held_variants)),
                    ", \"at_bound\": [", absl::StrJoin(c.bound_params, ", ", [](std::string* o, const std::string& n) { o->append(JsonQuote(n)); }), "]",
                    ", \"delta_bic\": ",
                    Num(c.bic - base.bic));
    if (std::find(named.begin(), named.end(), &c) == named.end())
      absl::StrAppend(&j, ", \"why_not\": ", JsonQuote(why_not(c)));
    absl::StrAppend(&j, "}");
    return j;
  };
  std::string json = absl::StrCat("{\"name\": ", JsonQuote(d.name()), ", \"verdict\": ", JsonQuote(verdict),
                                  ", \"effects\": [");
  for (size_t i = 0; i < named.size(); ++i) absl::StrAppend(&json, i ? ", " : "", effect_json(*named[i]));
  absl::StrAppend(&json, "], \"errors\": {\"baseline_train\": ", Num(base.train),
                  ", \"baseline_held_out\": ", Num(base.held),
                  ", \"baseline_held_out_variants\": ", NumList(base.held_variants),
                  ", \"noise_floor_held_out\": ", Num(floor_sd), ", \"weighting\": ",
                  JsonQuote(d.weighting()), ", \"training_weights\": ", NumList(weights),
                  ", \"training_floors\": ", NumList(train_floors));
  if (!named.empty())
    absl::StrAppend(&json, ", \"train\": ", Num(named[0]->train), ", \"held_out\": ",
                    Num(named[0]->held));
  absl::StrAppend(&json, "}, \"runners_up\": [");
  int k = 0;
  for (const auto& c : full) {
    if (!named.empty() && &c == named[0]) continue;
    absl::StrAppend(&json, k++ ? ", " : "", effect_json(c));
  }
  absl::StrAppend(&json, "], \"screening\": [");
  k = 0;
  for (const auto& c : screened)
    absl::StrAppend(&json, k++ ? ", " : "", "{\"id\": ", JsonQuote(c.label), ", \"train\": ",
                    Num(c.train), "}");
  std::string experiment;
  if (verdict == "ambiguous")
    for (const auto* c : named)
      if (const auto* e = effects::FindEffect(c->effects[0])) experiment += e->experiment + " ";
  // The figure's overlays: the baseline and the named explanation (or, with none named, the
  // fit closest held out) simulated on the held-out recordings.
  const Candidate* shown = named.empty() ? nullptr : named[0];
  if (!shown)
    for (const auto& c : full)
      if (c.ok && std::isfinite(c.held) && (!shown || c.held < shown->held)) shown = &c;
  std::string overlay = "{\"baseline_eval\": ";
  if (std::isfinite(base.held_variants[0]))  // evaluated into baseline-held by ScoreHeldOut
    absl::StrAppend(&overlay, JsonQuote(dir + "/baseline-held/eval.json"));
  else
    absl::StrAppend(&overlay, "null");
  if (shown && std::isfinite(HeldOutError(*shown, held_files, d, dir + "/explanation-held")))
    absl::StrAppend(&overlay, ", \"other_eval\": ", JsonQuote(dir + "/explanation-held/eval.json"),
                    ", \"other\": ", JsonQuote(named.empty() ? "closest rejected: " + shown->label
                                                          : shown->label));
  absl::StrAppend(&overlay, "}");
  // The located readings against the model's own spread; for "none", what they mean.
  const SpreadReading spread = ReadSpread(located, located_held);
  const NoneReading none =
      verdict == "none" ? ReadNone(spread, held_files, shown ? shown->label : "") : NoneReading{};
  if (!none.experiment.empty()) experiment = none.experiment;
  absl::StrAppend(&json, "], \"refitted_singles\": ", singles, ", \"reused_fits\": ", reused,
                  ", \"unexplained_mismatch\": ", none.unexplained ? "true" : "false",
                  ", \"located\": ", located, ", \"located_held_out\": ", located_held,
                  ", \"experiment\": ", JsonQuote(experiment), ", \"corrected_model\": ",
                  JsonQuote(corrected), ", \"compared_samples\": ", n, ", \"rule\": {\"margin\": ",
                  Num(rule.margin), ", \"held_out_gain\": ", Num(rule.held_out_gain),
                  ", \"paired_t\": ", Num(rule.paired_t), ", \"pair_gain\": ",
                  Num(rule.pair_gain), "}, \"overlay\": ", overlay);
  // The figures: drawn from the report itself, then listed in it (only those written).
  std::ofstream(dir + "/diagnosis.json") << json << "}\n";
  std::vector<std::string> figures;
  if (std::filesystem::exists(dir + "/located.svg")) figures.push_back(dir + "/located.svg");
  if (RunPlotScript({"diagnosis", "--report", dir + "/diagnosis.json", "--out",
                     dir + "/diagnosis.svg"}) == 0)
    figures.push_back(dir + "/diagnosis.svg");
  else
    std::cerr << "gaitforge: warning: the diagnosis figure could not be drawn "
                 "(clients/python/gaitforge_plot.py diagnosis; needs python3-matplotlib)\n";
  absl::StrAppend(&json, ", \"figures\": [",
                  absl::StrJoin(figures, ", ", [](std::string* o, const std::string& f) {
                    o->append(JsonQuote(f));
                  }),
                  "]}\n");
  std::ofstream(dir + "/diagnosis.json") << json;
  if (g.json) {
    std::cout << json;
  } else {
    std::cout << "diagnosis " << d.name() << ": ";
    if (verdict == "none") {
      std::cout << "no missing physics found: no candidate beat the baseline by the BIC margin ("
                << d.margin() << ") and cut its held-out error ("
                << absl::StrFormat("%.3g mm +- %.2g mm over numerically irrelevant variants",
                                   1000 * base.held, 1000 * floor_sd)
                << ") by " << static_cast<int>(rule.held_out_gain * 100)
                << "% with a paired t above " << rule.paired_t << " across the variants\n";
      if (!none.words.empty()) std::cout << "  " << none.words << "\n";
      if (!experiment.empty()) std::cout << "  " << experiment << "\n";
    } else {
      std::cout << (verdict == "found" ? "found " : "ambiguous between ");
      for (size_t i = 0; i < named.size(); ++i) std::cout << (i ? " and " : "") << named[i]->label;
      std::cout << "\n";
      for (const auto* c : named) {
        const auto* e = effects::FindEffect(c->effects[0]);
        if (e) std::cout << "  " << e->name << ": " << e->meaning << "\n";
        const FitRange& fr = ranges[c];
        for (size_t i = 0; i < c->genes.size() && i < c->values.size(); ++i) {
          std::string range;
          if (c->genes[i].name().rfind("nuisance.", 0) == 0) {
            range = "(the time offset: not a magnitude)";
          } else if (!std::isfinite(fr.tolerance) || i >= fr.params.size()) {
            range = "(no range: the model failed under a numeric variant, so no floor)";
          } else {
            const ParamRange& r = fr.params[i];
            auto end = [](double v, const char* open) {
              return std::isfinite(v) ? absl::StrFormat("%.4g", v) : std::string(open);
            };
            range = "range " + end(r.lo, "open") + " .. " + end(r.hi, "open");
            const double share = RangeShare(r, c->genes[i].lo(), c->genes[i].hi());
            if (share >= kUndeterminedShare)
              range += absl::StrFormat(" (%.0f%% of its allowed values: not pinned)", 100 * share);
          }
          std::cout << absl::StrFormat("    %-34s %12.5g  %s\n", c->genes[i].name(), c->values[i],
                                       range);
        }
        if (std::isfinite(fr.tolerance))
          std::cout << absl::StrFormat(
              "    (range: where the training error stays within %.3g mm of its least, the "
              "model's own spread; %d of %d evaluations)\n",
              1000 * fr.tolerance, fr.accepted, fr.evaluations);
      }
      std::cout << absl::StrFormat(
          "  held-out error %.4g -> %.4g mm, training %.4g -> %.4g mm, delta BIC %.1f\n",
          1000 * base.held, 1000 * named[0]->held, 1000 * base.train, 1000 * named[0]->train,
          named[0]->bic - base.bic);
      if (!experiment.empty()) std::cout << "  to tell them apart: " << experiment << "\n";
      std::cout << "  corrected model: " << corrected << "\n";
    }
    // Where it showed, in the locate script's words (its summary), then the files.
    google::protobuf::Struct where;
    if (google::protobuf::util::JsonStringToMessage(located, &where).ok() &&
        where.fields().count("summary"))
      std::cout << "  where it showed: " << where.fields().at("summary").string_value() << "\n";
    if (verdict != "none" && spread.train_known && !spread.train_beyond)
      std::cout << "  (no slice of the training residuals stands out beyond the model's numeric "
                   "spread on its own: the named effect shows in the calibration error, which "
                   "compares whole cycles)\n";
    std::cout << "  where the mismatch lives, by slice: " << dir
              << "/located.json and located.svg\n";
    if (std::find(figures.begin(), figures.end(), dir + "/diagnosis.svg") != figures.end())
      std::cout << "  held-out errors and overlays, before and after: " << dir
                << "/diagnosis.svg\n";
    if (static_cast<int>(singles) > d.top())
      std::cout << "  refitted " << singles << " leaders of the screening, not " << d.top()
                << ": the last within " << 100 * d.screening_tie() << "% of the " << d.top()
                << (d.top() == 1 ? "st" : d.top() == 2 ? "nd" : d.top() == 3 ? "rd" : "th")
                << " (a short fit cannot order near ties)\n";
    std::cout << "  runners-up, and why they lost:\n";
    for (const auto& c : full)
      if (std::find(named.begin(), named.end(), &c) == named.end())
        std::cout << absl::StrFormat("    %s (dBIC %.1f, held-out %.3g mm%s): %s\n", c.label,
                                     c.bic - base.bic, 1000 * c.held,
                                     c.at_bound ? ", at the edge of its range: " +
                                                      absl::StrJoin(c.bound_params, ", ")
                                                : std::string(),
                                     why_not(c));
    std::cout << "  report: " << dir << "/diagnosis.json\n";
  }
  return kOk;
}

}  // namespace gaitforge::cli
