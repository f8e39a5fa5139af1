// A diagnosis report in words (words.h).
#include "services/diagnosis/words.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"
#include "services/diagnosis/locate.h"
#include "services/core/file_text.h"
#include "services/diagnosis/plan.h"
#include "services/diagnosis/range.h"
#include "services/diagnosis/struct_fields.h"
#include "workers/effects/effects.h"

namespace gaitforge::diagnosis {
namespace {

using google::protobuf::Struct;
using google::protobuf::Value;

double N(const Struct& s, const std::string& k) { return Number(s, k, NAN); }
std::string S(const Struct& s, const std::string& k) { return Field(s, k).string_value(); }
const Struct& O(const Struct& s, const std::string& k) { return Field(s, k).struct_value(); }
std::string Json(const Value& v) {
  std::string out;
  if (v.kind_case() != Value::kStructValue ||
      !google::protobuf::util::MessageToJsonString(v.struct_value(), &out).ok())
    return "{}";
  return out;
}

std::string End(double v) { return std::isfinite(v) ? absl::StrFormat("%.4g", v) : "open"; }

// How the report's errors read (its rule's error_scale and error_unit; older reports: mm).
struct Unit {
  double scale = 1000;
  std::string label = "mm";
};
Unit UnitOf(const Struct& r) {
  Unit u;
  const Struct& rule = O(r, "rule");
  if (std::isfinite(N(rule, "error_scale"))) u.scale = N(rule, "error_scale");
  if (!S(rule, "error_unit").empty()) u.label = S(rule, "error_unit");
  return u;
}

// One named effect: its meaning, and each parameter's value with its range.
std::string Named(const Struct& e, const Unit& u) {
  std::string out;
  const std::string id = S(e, "id");
  // The report names its effects (a robot's own suspects are not in the catalog); reports
  // written before it did are read through the catalog.
  if (!S(e, "name").empty())
    absl::StrAppend(&out, "  ", S(e, "name"), ": ", S(e, "meaning"), "\n");
  else if (const auto* info = effects::FindEffect(id.substr(0, id.find('+'))))
    absl::StrAppend(&out, "  ", info->name, ": ", info->meaning, "\n");
  const double tolerance = N(e, "range_tolerance");
  std::vector<std::pair<double, std::string>> order;  // the genes' order, as fitted
  for (const auto& [name, pv] : O(e, "params").fields())
    order.emplace_back(N(pv.struct_value(), "index"), name);
  std::sort(order.begin(), order.end());
  for (const auto& [index, name] : order) {
    const Struct& p = O(e, "params").fields().at(name).struct_value();
    std::string range;
    if (name.rfind("nuisance.", 0) == 0) {
      range = "(the time offset: not a magnitude)";
    } else if (!std::isfinite(tolerance) || Field(p, "range").kind_case() != Value::kListValue) {
      range = "(no range: the model failed under a numeric variant, so no floor)";
    } else {
      const auto& r = Field(p, "range").list_value().values();
      auto num = [](const Value& v) {
        return v.kind_case() == Value::kNumberValue ? v.number_value() : NAN;
      };
      range = "range " + End(num(r[0])) + " .. " + End(num(r[1]));
      if (N(p, "range_share") >= kUndeterminedShare)
        range += absl::StrFormat(" (%.0f%% of its allowed values: not pinned)",
                                 100 * N(p, "range_share"));
    }
    absl::StrAppend(&out, absl::StrFormat("    %-34s %12.5g  %s\n", name, N(p, "value"), range));
  }
  if (std::isfinite(tolerance))
    absl::StrAppend(&out, absl::StrFormat(
                              "    (range: where the training error stays within %.3g %s of "
                              "its least, the model's own spread; %d of %d evaluations)\n",
                              u.scale * tolerance, u.label, static_cast<int>(N(e, "range_accepted")),
                              static_cast<int>(N(e, "range_evaluations"))));
  return out;
}

// Whether every part of a named explanation is structural (the report's `structural` lists
// them; absent in reports from before session 40).
bool AllStructural(const Struct& e) {
  if (Field(e, "structural").kind_case() != Value::kListValue) return false;
  const std::vector<std::string> parts = absl::StrSplit(S(e, "id"), '+');
  return Field(e, "structural").list_value().values_size() == static_cast<int>(parts.size());
}

std::string Verdict(const Struct& r) {
  const Unit u = UnitOf(r);
  const Struct& err = O(r, "errors");
  const Struct& rule = O(r, "rule");
  const std::string experiment = S(r, "experiment");
  std::string out;
  if (Field(r, "numerics").kind_case() == Value::kStructValue) {
    const Struct& nu = O(r, "numerics");
    absl::StrAppend(&out, absl::StrFormat(
                              "the model's numerics: its %.3g ms step missed the training "
                              "recordings by %.3g %s, %.3g ms by %.3g %s, so the diagnosis ran "
                              "at %.3g ms\n",
                              N(nu, "from_ms"), u.scale * N(nu, "from_training_error"), u.label,
                              N(nu, "at_ms"), u.scale * N(nu, "at_training_error"), u.label,
                              N(nu, "at_ms")));
  }
  if (Field(r, "resolution").kind_case() == Value::kListValue)
    for (const Value& v : Field(r, "resolution").list_value().values()) {
      const Struct& m = v.struct_value();
      absl::StrAppend(&out, absl::StrFormat(
                                "the model's resolution: with %s = %.0f it missed the training "
                                "recordings by %.3g %s, with %.0f by %.3g %s, so the diagnosis "
                                "ran at %s = %.0f\n",
                                S(m, "count"), N(m, "from"), u.scale * N(m, "from_training_error"),
                                u.label, N(m, "at"), u.scale * N(m, "at_training_error"), u.label,
                                S(m, "count"), N(m, "at")));
    }
  if (Field(r, "structure").kind_case() == Value::kStructValue) {
    const Struct& st = O(r, "structure");
    absl::StrAppend(&out, absl::StrFormat("the model's structure: %s, fitted into the baseline "
                                          "(delta BIC %.1f); effects were sought on top of it\n",
                                          S(st, "id"), N(st, "delta_bic")),
                    Named(st, u));
  }
  if (S(r, "verdict") == "none") {
    absl::StrAppend(
        &out, absl::StrFormat(
                  "no missing physics found: no candidate beat the baseline by the BIC margin "
                  "(%g) and cut its held-out error (%.3g %s +- %.2g %s over numerically "
                  "irrelevant variants) by %d%% with a paired t above %g across the variants\n",
                  N(rule, "margin"), u.scale * N(err, "baseline_held_out"), u.label,
                  u.scale * N(err, "noise_floor_held_out"), u.label,
                  static_cast<int>(N(rule, "held_out_gain") * 100), N(rule, "paired_t")));
    if (!S(r, "none_reading").empty()) absl::StrAppend(&out, "  ", S(r, "none_reading"), "\n");
    if (!S(r, "numerics_note").empty()) absl::StrAppend(&out, "  caution: ", S(r, "numerics_note"), "\n");
    if (!experiment.empty()) absl::StrAppend(&out, "  ", experiment, "\n");
    return out;
  }
  const auto& effects = Field(r, "effects").list_value().values();
  std::vector<std::string> labels;
  for (const auto& e : effects) labels.push_back(S(e.struct_value(), "id"));
  absl::StrAppend(&out, S(r, "verdict") == "found" ? "found " : "ambiguous between ",
                  absl::StrJoin(labels, " and "), "\n");
  for (const auto& e : effects) absl::StrAppend(&out, Named(e.struct_value(), u));
  const Struct& first = effects.empty() ? err : effects[0].struct_value();
  if (AllStructural(first))
    absl::StrAppend(&out, "  ", S(first, "id"),
                    " corrects the model's own idealisations (its structure), not physics it "
                    "left out: this robot differs from the model there, and nothing was found "
                    "on top of it\n");
  absl::StrAppend(&out, absl::StrFormat(
                            "  held-out error %.4g -> %.4g %s, training %.4g -> %.4g %s, delta "
                            "BIC %.1f\n",
                            u.scale * N(err, "baseline_held_out"), u.scale * N(first, "held_out"),
                            u.label, u.scale * N(err, "baseline_train"),
                            u.scale * N(first, "train"), u.label,
                            N(first, "delta_bic")));
  if (!S(r, "numerics_note").empty()) absl::StrAppend(&out, "  caution: ", S(r, "numerics_note"), "\n");
  if (!experiment.empty()) absl::StrAppend(&out, "  to tell them apart: ", experiment, "\n");
  absl::StrAppend(&out, "  corrected model: ", S(r, "corrected_model"), "\n");
  return out;
}

// Where it showed (the locate script's summary), the figures, near ties and runners-up.
std::string Details(const Struct& r, const std::string& dir) {
  const Unit u = UnitOf(r);
  std::string out;
  if (!S(O(r, "located"), "summary").empty())
    absl::StrAppend(&out, "  where it showed: ", S(O(r, "located"), "summary"), "\n");
  const SpreadReading spread = ReadSpread(Json(Field(r, "located")), Json(Field(r, "located_held_out")));
  if (S(r, "verdict") != "none" && spread.train_known && !spread.train_beyond)
    absl::StrAppend(&out,
                    "  (no slice of the training residuals stands out beyond the model's numeric "
                    "spread on its own: the named effect shows in the calibration error, which "
                    "compares whole cycles)\n");
  // Only what was written, as the report records it: locating fails on recordings it cannot
  // slice (the report's `located` is then empty, and no located.svg is among its figures).
  const bool json = Field(r, "located").struct_value().fields_size() > 0;
  bool svg = false;
  for (const auto& f : Field(r, "figures").list_value().values())
    svg = svg || std::filesystem::path(f.string_value()).filename() == "located.svg";
  if (json || svg)
    absl::StrAppend(&out, "  where the mismatch lives, by slice: ", dir, "/",
                    json && svg ? "located.json and located.svg" : json ? "located.json" : "located.svg",
                    "\n");
  else
    absl::StrAppend(&out, "  where the mismatch lives: not located (locating wrote nothing for these recordings; "
                    "the coordinator's log has its warning)\n");
  for (const auto& f : Field(r, "figures").list_value().values())
    if (std::filesystem::path(f.string_value()).filename() == "diagnosis.svg")
      absl::StrAppend(&out, "  held-out errors and overlays, before and after: ", dir,
                      "/diagnosis.svg\n");
  const int top = static_cast<int>(N(r, "top")), singles = static_cast<int>(N(r, "refitted_singles"));
  if (singles > top)
    absl::StrAppend(&out, absl::StrFormat("  refitted %d leaders of the screening, not %d: the "
                                          "last within %g%% of the best %d (a short fit cannot "
                                          "order near ties)\n",
                                          singles, top, 100 * N(r, "screening_tie"), top));
  absl::StrAppend(&out, "  runners-up, and why they lost:\n");
  for (const auto& v : Field(r, "runners_up").list_value().values()) {
    const Struct& c = v.struct_value();
    std::vector<std::string> bound;
    for (const auto& b : Field(c, "at_bound").list_value().values()) bound.push_back(b.string_value());
    absl::StrAppend(&out, absl::StrFormat(
                              "    %s (dBIC %.1f, held-out %.3g %s%s): %s\n", S(c, "id"),
                              N(c, "delta_bic"), u.scale * N(c, "held_out"), u.label,
                              bound.empty() ? std::string()
                                            : ", at the edge of its range: " +
                                                  absl::StrJoin(bound, ", "),
                              S(c, "why_not")));
  }
  absl::StrAppend(&out, "  report: ", dir, "/diagnosis.json\n");
  return out;
}

// The recordings that would decide (plan.h, WhyPlan): the plan the diagnosis kept beside
// its report (dir/plan.json) in words, or how to make one. A named effect that a recording
// given already parts from the baseline has no plan, and needs no words.
std::string PlanPart(const std::string& report_json, const std::string& dir) {
  const plan::PlanReason why = plan::WhyPlan(report_json);
  if (why == plan::PlanReason::kNone) return "";
  const auto text = core::ReadWholeFile(dir + "/plan.json");
  auto words = plan::PlanWords(text.value_or(""), dir + "/plan.json");
  const bool planned = text.ok() && words.ok();
  if (why == plan::PlanReason::kConfirm) {
    if (!planned) return "";
    double decisive = NAN;
    const std::string named = plan::FirstNamed(report_json);
    const double given = plan::RecordedSeparation(*text, named, &decisive);
    if (!std::isfinite(given))  // the plan could not compare it (a fit it left out)
      return absl::StrFormat("to confirm %s, the recordings that would part it from the model "
                             "without it (%s/plan.json):\n%s",
                             named, dir, *words);
    return absl::StrFormat(
        "to confirm %s: no recording given parts it from the model without it by more than "
        "%.2g times what the model leaves unexplained (%g would decide); the recordings that "
        "would (%s/plan.json):\n%s",
        named, given, decisive, dir, *words);
  }
  const std::string what = why == plan::PlanReason::kUnexplained
                               ? "nothing named explains the held-out mismatch; the recordings "
                                 "that would tell the nearest explanations apart"
                               : "the recordings that would decide";
  if (planned) return absl::StrCat(what, " (", dir, "/plan.json):\n", *words);
  return absl::StrCat("  ", what, ": gaitforge diagnose plan SPEC --report ", dir,
                      "/diagnosis.json (docs/diagnosis.md, \"Plan the experiment that "
                      "decides\")\n");
}

}  // namespace

absl::StatusOr<std::string> ReportWords(const std::string& report_json, const std::string& dir) {
  Struct r;
  if (auto s = google::protobuf::util::JsonStringToMessage(report_json, &r); !s.ok())
    return absl::InvalidArgumentError(
        absl::StrCat("the diagnosis report is not JSON: ", s.message().as_string()));
  const std::string where = dir.empty() ? S(r, "dir") : dir;
  std::string verdict = Verdict(r);
  if (!dir.empty()) {  // the corrected model is among the files copied to dir
    const std::string was = S(r, "corrected_model");
    if (const size_t at = verdict.find(was); !was.empty() && at != std::string::npos)
      verdict.replace(at, was.size(), where + "/corrected-model.yaml");
  }
  return absl::StrCat("diagnosis ", S(r, "name"), ": ", verdict, Details(r, where),
                      PlanPart(report_json, where));
}

}  // namespace gaitforge::diagnosis
