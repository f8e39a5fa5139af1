#include "services/coordinator/validation_model.h"

#include <set>
#include <vector>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/str_split.h"
#include "absl/strings/strip.h"
#include "services/coordinator/corrected_model.h"

namespace gaitforge::coordinator {
namespace {

constexpr char kField[] = "validate.from_calibration";

std::string Name(absl::string_view item) {
  return std::string(absl::StripAsciiWhitespace(item.substr(0, item.find('='))));
}

}  // namespace

std::string MergeSets(const std::string& first, const std::string& second) {
  std::vector<std::string> items;
  for (absl::string_view item : absl::StrSplit(first, ',', absl::SkipWhitespace()))
    items.emplace_back(absl::StripAsciiWhitespace(item));
  std::set<std::string> names;
  for (const auto& item : items) names.insert(Name(item));
  for (absl::string_view item : absl::StrSplit(second, ',', absl::SkipWhitespace()))
    if (!names.count(Name(item))) items.emplace_back(absl::StripAsciiWhitespace(item));
  return absl::StrJoin(items, ",");
}

absl::Status RebaseOnCalibration(storage::StudyStore& store, const SpreadFn& spread_after,
                                 const std::string& id, v1::StudySpec* study) {
  const v1::ObjectiveSpec own = study->objective();
  if (own.robust().samples_size() > 0 && own.robust().sampling() != "fits")
    return absl::InvalidArgumentError(absl::StrCat(
        kField, ": the study's ensemble lists joint samples of its own (objective.robust."
        "samples); they belong to its model, so calibration ", id, "'s cannot replace it"));
  v1::StudySpec fresh;
  v1::ObjectiveSpec* o = fresh.mutable_objective();
  *o = own;
  o->clear_from_diagnosis();
  o->mutable_options()->erase("set");
  o->mutable_robust()->clear_parameters();
  o->mutable_robust()->clear_samples();
  o->set_from_calibration(id);
  if (auto s = ResolveFromCalibration(store, spread_after, &fresh); !s.ok())
    return absl::Status(s.code(), absl::StrCat(kField, ": ",
                                               absl::StripPrefix(s.message(), "objective.from_calibration: ")));
  const std::string own_set = own.options().count("set") ? own.options().at("set") : "";
  const std::string set = MergeSets(o->options().count("set") ? o->options().at("set") : "",
                                    own_set);
  if (!set.empty()) (*o->mutable_options())["set"] = set;
  if (own.robust().sampling() != "fits")
    for (const auto& p : own.robust().parameters())
      if (!ListsRange(*o, p.name())) *o->mutable_robust()->add_parameters() = p;  // log too
  *study->mutable_objective() = std::move(*o);
  return absl::OkStatus();
}

}  // namespace gaitforge::coordinator
