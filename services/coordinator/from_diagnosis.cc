#include "services/coordinator/from_diagnosis.h"

#include <yaml-cpp/yaml.h>

#include <cmath>

#include "absl/strings/str_cat.h"
#include "services/coordinator/corrected_model.h"
#include "gaitforge/v1/diagnosis.pb.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"

namespace gaitforge::coordinator {
namespace {

using google::protobuf::Struct;
using google::protobuf::Value;

const std::string kField = "objective.from_diagnosis";

// The fitted ranges of the named explanation's parameters (every effect it names):
// (name, lo, hi).
std::vector<std::tuple<std::string, double, double>> FittedRanges(const std::string& report) {
  Struct r;
  if (!google::protobuf::util::JsonStringToMessage(report, &r).ok()) return {};
  const auto effects = r.fields().find("effects");
  if (effects == r.fields().end()) return {};
  std::vector<std::tuple<std::string, double, double>> out;
  for (const Value& effect : effects->second.list_value().values()) {
    const auto params = effect.struct_value().fields().find("params");
    if (params == effect.struct_value().fields().end()) continue;
    for (const auto& [name, v] : params->second.struct_value().fields()) {
      const auto& f = v.struct_value().fields();
      if (!f.count("value") || !f.count("sd") || !f.count("range")) continue;  // the time offset
      const double value = f.at("value").number_value(), sd = f.at("sd").number_value();
      const auto& range = f.at("range").list_value();
      const auto side = [&](int i, double open) {
        return range.values_size() == 2 && range.values(i).kind_case() == Value::kNumberValue
                   ? range.values(i).number_value()
                   : open;
      };
      const double lo = side(0, value - 2 * sd), hi = side(1, value + 2 * sd);
      if (std::isfinite(lo) && std::isfinite(hi) && lo < hi) out.emplace_back(name, lo, hi);
    }
  }
  return out;
}

}  // namespace

absl::Status ResolveFromDiagnosis(storage::StudyStore& store, v1::StudySpec* spec) {
  auto* o = spec->mutable_objective();
  const std::string id = o->from_diagnosis();
  if (id.empty()) return absl::OkStatus();
  auto rec = store.GetDiagnosis(id, true);
  if (!rec.ok())
    return absl::NotFoundError(absl::StrCat(kField, ": no diagnosis with id '", id, "'"));
  if (rec->state != "completed")
    return absl::FailedPreconditionError(absl::StrCat(
        kField, ": diagnosis ", id, " is ", rec->state, "; a study starts from a completed one"));
  std::string corrected, robot;  // robot: the descriptor the corrected model names, if any
  for (const auto& [name, content] : rec->files) {
    if (name == "corrected-model.yaml") corrected = content;
    if (name == "robot.yaml") robot = content;
  }
  if (corrected.empty())
    return absl::FailedPreconditionError(absl::StrCat(
        kField, ": diagnosis ", id, " named no explanation (verdict '", rec->verdict,
        "'), so it has no corrected model"));
  const YAML::Node model = YAML::Load(corrected)["objective"];
  const std::string name = model["name"].as<std::string>();
  if (!o->name().empty() && o->name() != name)
    return absl::InvalidArgumentError(absl::StrCat(
        kField, ": diagnosis ", id, "'s corrected model is ", name, ", not ", o->name()));
  o->set_name(name);
  v1::DiagnosisSpec d;
  d.ParseFromString(rec->spec);
  if (o->robot().empty() && o->robot_descriptor().empty() && name == "robot.distance") {
    o->set_robot(d.robot());
    o->set_robot_descriptor(robot.empty() ? d.robot_descriptor() : robot);
  }
  PrependSet(o, model["options"]["set"].as<std::string>(""));
  if (!o->has_robust()) return absl::OkStatus();
  for (const auto& [param, lo, hi] : FittedRanges(rec->report)) AddEnsembleRange(o, param, lo, hi);
  return absl::OkStatus();
}

}  // namespace gaitforge::coordinator
