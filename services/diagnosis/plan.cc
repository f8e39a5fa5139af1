// The pure parts of `gaitforge diagnose plan` (plan.h).
#include "services/diagnosis/plan.h"

#include <algorithm>
#include <cmath>
#include <set>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"
#include "services/core/keyed_rng.h"
#include "services/diagnosis/struct_fields.h"

namespace gaitforge::diagnosis::plan {
namespace {

using google::protobuf::ListValue;
using google::protobuf::Struct;
using google::protobuf::Value;


absl::StatusOr<Struct> Parse(const std::string& json, const std::string& where) {
  Struct report;
  if (auto s = google::protobuf::util::JsonStringToMessage(json, &report); !s.ok())
    return absl::InvalidArgumentError(
        absl::StrCat(where, ": not a diagnosis report (JSON): ", s.message().ToString()));
  return report;
}

// A fit's parameter values, without the recordings' nuisance parameters.
Explanation FromFit(const std::string& id, const Struct& fit, double train) {
  Explanation e{id, {}, Number(fit, "train", train)};
  for (const auto& [name, p] : Field(fit, "params").struct_value().fields()) {
    if (name.rfind("nuisance.", 0) == 0) continue;
    const double v = Number(p.struct_value(), "value", NAN);
    if (std::isfinite(v)) e.set.emplace_back(name, v);
  }
  std::sort(e.set.begin(), e.set.end());
  return e;
}

bool Usable(const Struct& fit) {
  const bool bound = Field(fit, "at_bound").list_value().values_size() > 0;
  return !bound && std::isfinite(Number(fit, "held_out", NAN)) &&
         !Field(fit, "id").string_value().empty();
}

}  // namespace

void AddFlags(core::Flags& flags, Options* o, const std::string& command) {
  const std::string c = command + ": ";
  flags.Add("report", &o->report, c + "the diagnosis's report (diagnosis.json)");
  flags.Add("propose", &o->propose, c + "recordings to propose (1..20)");
  flags.Add("random", &o->random, c + "random gaits among the candidates (0..1000)");
  flags.Add("rivals", &o->rivals,
            c + "fitted explanations beside the baseline to separate (1..10)");
  flags.Add("seed", &o->seed, c + "seed of the random gaits");
  flags.Add("decisive", &o->decisive,
            c + "a pair parted by this many times the model's residual is decided (above 0)");
}

absl::Status Check(const Options& o) {
  auto bad = [](const std::string& flag, const std::string& range, double v) {
    return absl::InvalidArgumentError(absl::StrFormat("--%s %g: %s", flag, v, range));
  };
  if (o.propose < 1 || o.propose > 20) return bad("propose", "1..20", o.propose);
  if (o.random < 0 || o.random > 1000) return bad("random", "0..1000", o.random);
  if (o.rivals < 1 || o.rivals > 10) return bad("rivals", "1..10", o.rivals);
  if (!(o.decisive > 0 && std::isfinite(o.decisive))) return bad("decisive", "above 0", o.decisive);
  if (o.max_shift < 0 || o.max_shift > 1000) return bad("max-shift", "0..1000", o.max_shift);
  if (o.threads < 1 || o.threads > 256) return bad("threads", "1..256", o.threads);
  return absl::OkStatus();
}

std::vector<std::string> Arguments(const Options& o) {
  return {"--report", o.report, "--propose", absl::StrCat(o.propose), "--random",
          absl::StrCat(o.random), "--rivals", absl::StrCat(o.rivals), "--seed",
          absl::StrCat(o.seed), "--decisive", absl::StrFormat("%.17g", o.decisive),
          "--max-shift", absl::StrCat(o.max_shift), "--threads", absl::StrCat(o.threads)};
}

absl::StatusOr<std::vector<Explanation>> ExplanationsFromReport(const std::string& json,
                                                                const std::string& where,
                                                                int rivals) {
  auto report = Parse(json, where);
  if (!report.ok()) return report.status();
  const double base_train =
      Number(Field(*report, "errors").struct_value(), "baseline_train", NAN);
  std::vector<Explanation> out;
  const Struct& baseline = Field(*report, "baseline").struct_value();
  out.push_back(FromFit("none", baseline, base_train));
  std::vector<const Struct*> runners;
  for (const Value& v : Field(*report, "runners_up").list_value().values()) {
    const Struct& f = v.struct_value();
    if (Usable(f) && Number(f, "delta_bic", 0) < 0) runners.push_back(&f);
  }
  std::stable_sort(runners.begin(), runners.end(), [](const Struct* a, const Struct* b) {
    return Number(*a, "held_out", 0) < Number(*b, "held_out", 0);
  });
  std::vector<const Struct*> fits;
  for (const Value& v : Field(*report, "effects").list_value().values())
    if (Usable(v.struct_value())) fits.push_back(&v.struct_value());
  fits.insert(fits.end(), runners.begin(), runners.end());
  std::set<std::string> seen;
  for (const Struct* f : fits) {
    const std::string id = Field(*f, "id").string_value();
    if (static_cast<int>(out.size()) > rivals || !seen.insert(id).second) continue;
    out.push_back(FromFit(id, *f, base_train));
  }
  if (out.size() < 2)
    return absl::InvalidArgumentError(absl::StrCat(
        where, ": the report holds no fitted explanation beside the baseline (no candidate "
               "fitted the training data better than the model without it): there is nothing "
               "for an experiment to separate; diagnose with more candidates first"));
  return out;
}

bool Undecided(const std::string& report_json) {
  auto r = Parse(report_json, "");
  if (!r.ok()) return false;
  const std::string verdict = Field(*r, "verdict").string_value();
  if (verdict == "ambiguous") return true;
  if (verdict != "none") return false;
  const double margin = Number(Field(*r, "rule").struct_value(), "margin", 10);
  for (const Value& v : Field(*r, "runners_up").list_value().values()) {
    const Struct& f = v.struct_value();
    if (Number(f, "delta_bic", 0) < -margin && Field(f, "at_bound").list_value().values_size() == 0)
      return true;
  }
  return false;
}

PlanReason WhyPlan(const std::string& report_json) {
  if (Undecided(report_json)) return PlanReason::kUndecided;
  auto r = Parse(report_json, "");
  if (!r.ok()) return PlanReason::kNone;
  const std::string verdict = Field(*r, "verdict").string_value();
  if (verdict == "found") return PlanReason::kConfirm;
  if (verdict != "none" || !Field(*r, "unexplained_mismatch").bool_value()) return PlanReason::kNone;
  for (const Value& v : Field(*r, "runners_up").list_value().values())
    if (Usable(v.struct_value()) && Number(v.struct_value(), "delta_bic", 0) < 0)
      return PlanReason::kUnexplained;
  return PlanReason::kNone;
}

std::string FirstNamed(const std::string& report_json) {
  auto r = Parse(report_json, "");
  if (!r.ok()) return "";
  const auto& effects = Field(*r, "effects").list_value().values();
  return effects.empty() ? "" : Field(effects[0].struct_value(), "id").string_value();
}

double RecordedSeparation(const std::string& plan_json, const std::string& id, double* decisive) {
  auto p = Parse(plan_json, "");
  if (!p.ok()) return NAN;
  if (decisive) *decisive = Number(*p, "decisive", NAN);
  const auto& explanations = Field(*p, "explanations").list_value().values();
  int base = -1, named = -1;
  for (int i = 0; i < explanations.size(); ++i) {
    const std::string e = Field(explanations[i].struct_value(), "id").string_value();
    if (e == "none") base = i;
    if (e == id) named = i;
  }
  if (base < 0 || named < 0) return NAN;
  const auto pairs = Pairs(explanations.size());
  const auto at = std::find(pairs.begin(), pairs.end(),
                            std::make_pair(std::min(base, named), std::max(base, named)));
  const int pair = static_cast<int>(at - pairs.begin());
  double best = NAN;
  for (const Value& v : Field(*p, "candidates").list_value().values()) {
    const Struct& c = v.struct_value();
    const auto& ratio = Field(c, "ratio").list_value().values();
    if (Field(c, "kind").string_value() != "recorded" || pair >= ratio.size()) continue;
    const double x = ratio[pair].number_value();
    if (std::isfinite(x) && !(x <= best)) best = x;
  }
  return best;
}

absl::StatusOr<ReportModel> ReportModelOf(const std::string& json, const std::string& where) {
  auto report = Parse(json, where);
  if (!report.ok()) return report.status();
  ReportModel m;
  for (const Value& v : Field(*report, "resolution").list_value().values()) {
    const Struct& move = v.struct_value();
    const std::string count = Field(move, "count").string_value();
    const int at = static_cast<int>(Number(move, "at", 0));
    auto same = std::find_if(m.counts.begin(), m.counts.end(),
                             [&](const auto& c) { return c.first == count; });
    if (same != m.counts.end()) same->second = at;
    else if (!count.empty() && at > 0) m.counts.emplace_back(count, at);
  }
  m.timestep_ms = Number(Field(*report, "numerics").struct_value(), "at_ms", 0);
  return m;
}

namespace {

// The gene index of the period T or the frequency f, and whether it is a frequency; -1 if
// the controller has neither.
std::pair<int, bool> PeriodGene(const robots::Controller& c) {
  for (size_t k = 0; k < c.genes.size(); ++k) {
    if (c.genes[k].name == "T") return {static_cast<int>(k), false};
    if (c.genes[k].name == "f") return {static_cast<int>(k), true};
  }
  return {-1, false};
}

}  // namespace

std::vector<Experiment> Candidates(const robots::RobotDescriptor& d,
                                   const std::vector<Recorded>& recorded, int random,
                                   uint64_t seed) {
  const auto& genes = d.controller.genes;
  const auto [period, frequency] = PeriodGene(d.controller);
  std::vector<Experiment> out;
  int longest = 1;
  for (const Recorded& r : recorded) {
    longest = std::max(longest, r.cycles);
    out.push_back({r.name, "recorded", r.genes, r.cycles});
    out.push_back({r.name + ", three times as long", "longer", r.genes, 3 * r.cycles});
    for (double scale : {0.5, 2.0}) {
      if (period < 0) break;
      std::vector<double> g = r.genes;
      g[period] = frequency ? g[period] / scale : g[period] * scale;
      if (g[period] < genes[period].lo || g[period] > genes[period].hi) continue;
      out.push_back({absl::StrFormat("%s, period x%g", r.name, scale), "period", g, r.cycles});
    }
  }
  for (int i = 0; i < random; ++i) {
    core::KeyedRng rng(seed, 0, static_cast<uint64_t>(i), core::Purpose::kPlan);
    std::vector<double> g;
    for (const auto& gene : genes) g.push_back(rng.Uniform(gene.lo, gene.hi));
    out.push_back({absl::StrCat("random gait ", i + 1), "random", g, longest});
  }
  return out;
}

std::vector<Experiment> PlaybackCandidates(const std::vector<std::string>& names) {
  std::vector<Experiment> out;
  for (int k = 0; k < static_cast<int>(names.size()); ++k) {
    const std::string& n = names[k];
    out.push_back({n, "recorded", {}, 0, k, {}});
    out.push_back({n + ", inputs x0.5", "scaled", {}, 0, k, {0.5, 1, -1}});
    out.push_back({n + ", inputs x1.5", "scaled", {}, 0, k, {1.5, 1, -1}});
    out.push_back({n + ", twice as slow", "slower", {}, 0, k, {1, 2, -1}});
    out.push_back({n + ", let go half-way", "released", {}, 0, k, {1, 1, 0.5}});
  }
  return out;
}

std::vector<std::pair<int, int>> Pairs(int n) {
  std::vector<std::pair<int, int>> out;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) out.emplace_back(i, j);
  return out;
}

std::vector<int> Choose(const std::vector<std::vector<double>>& ratio, int count,
                        double decisive) {
  const size_t pairs = ratio.empty() ? 0 : ratio[0].size();
  std::vector<double> cover(pairs, 0.0);
  std::vector<int> picked;
  auto usable = [&](size_t e) {
    return std::all_of(ratio[e].begin(), ratio[e].end(), [](double r) { return std::isfinite(r); });
  };
  while (static_cast<int>(picked.size()) < count) {
    int best = -1;
    double best_gain = 0;
    for (size_t e = 0; e < ratio.size(); ++e) {
      if (!usable(e) || std::find(picked.begin(), picked.end(), e) != picked.end()) continue;
      double gain = 0;
      for (size_t p = 0; p < pairs; ++p)
        gain += std::min(std::max(cover[p], ratio[e][p]), decisive) - std::min(cover[p], decisive);
      if (gain > best_gain + 1e-12) {
        best = static_cast<int>(e);
        best_gain = gain;
      }
    }
    if (best < 0) break;
    picked.push_back(best);
    for (size_t p = 0; p < pairs; ++p) cover[p] = std::max(cover[p], ratio[best][p]);
  }
  return picked;
}

namespace {

std::string PairName(const ListValue& pair) {
  if (pair.values_size() != 2) return "?";
  return absl::StrCat(pair.values(0).string_value(), " from ", pair.values(1).string_value());
}

// One proposed recording: its gait and what it separates.
std::string StepWords(int k, const Struct& c, const ListValue& pairs, double decisive) {
  std::vector<std::string> genes;
  for (const auto& [name, v] : Field(c, "genes").struct_value().fields())
    genes.push_back(absl::StrFormat("%s=%.4g", name, v.number_value()));
  std::sort(genes.begin(), genes.end());
  std::string out =
      genes.empty()
          ? absl::StrFormat("  %d. %s: %.3g s from rest\n", k + 1, Field(c, "name").string_value(),
                            Number(c, "duration_s", 0))
          : absl::StrFormat("  %d. %s: %d cycles of %.3g s from rest (%.3g s)\n     genes %s\n",
                            k + 1, Field(c, "name").string_value(),
                            static_cast<int>(Number(c, "cycles", 0)), Number(c, "period_s", 0),
                            Number(c, "duration_s", 0), absl::StrJoin(genes, " "));
  const ListValue& ratio = Field(c, "ratio").list_value();
  for (int p = 0; p < ratio.values_size() && p < pairs.values_size(); ++p) {
    const double r = ratio.values(p).number_value();
    if (r < decisive) continue;
    absl::StrAppend(&out, absl::StrFormat("     separates %s by %.1fx the residual\n",
                                          PairName(Field(pairs.values(p).struct_value(), "pair").list_value()), r));
  }
  return out;
}

}  // namespace

absl::StatusOr<std::string> PlanWords(const std::string& json, const std::string& where) {
  auto plan = Parse(json, where);
  if (!plan.ok()) return plan.status();
  const ListValue& steps = Field(*plan, "plan").list_value();
  const ListValue& pairs = Field(*plan, "pairs").list_value();
  const double decisive = Number(*plan, "decisive", 2);
  std::vector<std::string> ids;
  for (const Value& e : Field(*plan, "explanations").list_value().values())
    ids.push_back(Field(e.struct_value(), "id").string_value());
  std::string out = absl::StrFormat(
      "plan for %s: %d recording(s) to tell apart %s (residual %.3g, the best explanation's "
      "training error; a pair is decided at %gx)\n",
      Field(*plan, "robot").string_value(), steps.values_size(), absl::StrJoin(ids, ", "),
      Number(*plan, "residual", NAN), decisive);
  for (int k = 0; k < steps.values_size(); ++k)
    absl::StrAppend(&out, StepWords(k, steps.values(k).struct_value(), pairs, decisive));
  std::vector<std::string> open;
  for (const Value& v : pairs.values()) {
    const Struct& p = v.struct_value();
    if (Field(p, "decided").bool_value()) continue;
    open.push_back(absl::StrFormat("%s (best %.1fx)", PairName(Field(p, "pair").list_value()),
                                   Number(p, "best_ratio", 0)));
  }
  if (open.empty())
    absl::StrAppend(&out, "  every pair is decided by these recordings\n");
  else
    absl::StrAppend(&out, "  no candidate decides: ", absl::StrJoin(open, "; "),
                    " (the model's residual hides the difference: longer or other recordings "
                    "might tell)\n");
  if (steps.values_size() > 0)  // measured on the MuJoCo build: docs/diagnosis.md
    absl::StrAppend(&out, "  record them, add them to the spec's held_out (there the "
                          "explanations' predictions of them are compared) and diagnose again\n");
  return out;
}

}  // namespace gaitforge::diagnosis::plan
