#include "workers/models/caterpillar/param_overrides.h"

#include <cmath>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "services/core/objective_catalog.h"

namespace gaitforge::caterpillar {
namespace {

using P = CaterpillarParams;

const robots::RobotDescriptor& Robot() { return CaterpillarDescriptor(); }

std::string Num(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

double Get(const P& p, const std::string& name) { return *GetField(p, name); }

}  // namespace

const std::vector<std::string>& CalibratableParamNames() {
  static const std::vector<std::string> names = Robot().CalibratableNames();
  return names;
}

const std::vector<std::string>& NuisanceParamNames() {
  return core::FindObjective("caterpillar.calibration")->nuisance;
}

bool IsNuisanceParam(std::string_view name) {
  for (const auto& n : NuisanceParamNames()) {
    if (name == n) return true;
  }
  return false;
}

absl::Status ValidateCalibratableFields(const CaterpillarParams& params) {
  for (const robots::Parameter& f : Robot().parameters) {
    if (!f.calibratable) continue;
    if (std::string bad = f.Check(Get(params, f.name)); !bad.empty())
      return absl::InvalidArgumentError(bad);
  }
  return Robot().CheckRelations([&params](const std::string& n) { return Get(params, n); });
}

absl::Status SetParam(CaterpillarParams& params, std::string_view name_view, double value) {
  const std::string name(name_view);
  if (IsNuisanceParam(name)) {
    return absl::InvalidArgumentError(
        absl::StrCat(name,
                     " is a nuisance parameter of the comparison, handled by the calibration "
                     "objective, not a model parameter"));
  }
  P p = params;
  const robots::Parameter* f = Robot().FindParameter(name);
  const robots::Scale* scale = Robot().FindScale(name);
  if (f != nullptr && f->calibratable) {
    if (std::string bad = f->Check(value); !bad.empty()) return absl::InvalidArgumentError(bad);
    if (absl::Status s = SetField(p, name, value); !s.ok()) return s;
  } else if (scale != nullptr) {
    if (!std::isfinite(value) || !(value > 0)) {
      return absl::InvalidArgumentError(
          absl::StrCat(name, " = ", Num(value), " must be a positive finite factor"));
    }
    for (const std::string& field : scale->multiplies) {
      const double v = Get(p, field) * value;
      if (std::string bad = Robot().FindParameter(field)->Check(v); !bad.empty()) {
        return absl::InvalidArgumentError(absl::StrCat(name, " = ", Num(value), " makes ", bad));
      }
      if (absl::Status s = SetField(p, field, v); !s.ok()) return s;
    }
  } else {
    return absl::InvalidArgumentError(absl::StrCat(
        "unknown caterpillar calibration parameter '", name, "'; nearest: ",
        absl::StrJoin(robots::Nearest(name, CalibratableParamNames()), ", "),
        "; known: ", absl::StrJoin(CalibratableParamNames(), ", "),
        "; nuisance: ", absl::StrJoin(NuisanceParamNames(), ", ")));
  }
  if (absl::Status s = ValidateCalibratableFields(p); !s.ok()) {
    return absl::InvalidArgumentError(
        absl::StrCat("after ", name, " = ", Num(value), ": ", s.message()));
  }
  params = p;
  return absl::OkStatus();
}

}  // namespace gaitforge::caterpillar
