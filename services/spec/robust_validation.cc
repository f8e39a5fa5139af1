#include "services/spec/robust_validation.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "robots/numerics.h"
#include "workers/effects/effects.h"

namespace gaitforge::spec {
namespace {

constexpr int kMaxStartPhases = 64;
constexpr double kMaxK = 10;

std::string Objectives() {
  std::vector<std::string> names;
  for (const auto& o : core::ObjectiveCatalog())
    if (o.robust) names.push_back(o.name);
  return absl::StrJoin(names, ", ");
}

// Why `name` may not take values in [lo, hi] on this robot; empty when it may.
std::string RangeError(const robots::RobotDescriptor& robot, const std::string& name, double lo,
                       double hi) {
  // What the objective's option set accepts: the generic builder any parameter, a dedicated
  // model of its own (its descriptor's model is not generic) its calibratable ones; both
  // scales and effects.
  std::vector<std::string> known = effects::FittableNames(robot);
  if (robot.model == "generic")
    for (const robots::Parameter& p : robot.parameters) known.push_back(p.name);
  if (std::find(known.begin(), known.end(), name) == known.end())
    return absl::StrCat("'", name, "' is not a parameter the ensemble can vary on robot ",
                        robot.name, "; nearest: ", absl::StrJoin(robots::Nearest(name, known), ", "));
  if (const robots::Parameter* p = robot.FindParameter(name)) {
    for (double v : {lo, hi})
      if (std::string bad = p->Check(v); !bad.empty()) return bad;
    return "";
  }
  if (const robots::Scale* scale = robot.FindScale(name)) {
    if (!(lo > 0)) return absl::StrCat(name, " is a factor: lo = ", lo, " must be > 0");
    // The factor multiplies the descriptor's values: each product must stay in its range.
    for (const std::string& field : scale->multiplies)
      if (const robots::Parameter* p = robot.FindParameter(field))
        for (double f : {lo, hi})
          if (std::string bad = p->Check(f * p->value); !bad.empty())
            return absl::StrCat(name, " = ", f, " makes ", bad);
    return "";
  }
  if (const auto* e = effects::BuilderParam(name, robot))
    if (!(lo >= e->lo && hi <= e->hi))
      return absl::StrCat(name, " = [", lo, ", ", hi, "] ", e->unit, " leaves [", e->lo, ", ",
                          e->hi, "]");
  return "";
}

void ValidateNumerics(const gaitforge::v1::Robustness& r, const robots::RobotDescriptor& robot,
                      std::vector<FieldError>& e) {
  for (int i = 0; i < r.numerics_size(); ++i) {
    const std::string& item = r.numerics(i);
    if (item.empty()) continue;
    const std::string path = absl::StrCat("objective.robust.numerics[", i, "]");
    const size_t eq = item.find('=');
    double value;
    if (eq == std::string::npos || !absl::SimpleAtod(item.substr(eq + 1), &value)) {
      e.push_back({path, absl::StrCat("'", item, "' must be NAME=VALUE, \"\" (the model as it "
                                      "is) or the single word standard")});
      continue;
    }
    if (std::string bad = RangeError(robot, item.substr(0, eq), value, value); !bad.empty())
      e.push_back({path, bad});
  }
}

// The given samples: at most kMaxEnsembleMembers, each one value per parameter inside its
// range. `sampling` (from_calibration's choice) is one of "", box, fits.
void ValidateSamples(const gaitforge::v1::StudySpec& spec, std::vector<FieldError>& e) {
  const auto& r = spec.objective().robust();
  if (r.sampling() != "" && r.sampling() != "box" && r.sampling() != "fits")
    e.push_back({"objective.robust.sampling",
                 absl::StrCat("'", r.sampling(), "' is not one of box, fits")});
  else if (!r.sampling().empty() && spec.objective().from_calibration().empty())
    e.push_back({"objective.robust.sampling",
                 "chooses how a calibration's ranges are sampled; it needs "
                 "objective.from_calibration"});
  if (r.samples_size() > kMaxEnsembleMembers)
    e.push_back({"objective.robust.samples", absl::StrCat("holds ", r.samples_size(),
                                                          " samples; at most ", kMaxEnsembleMembers)});
  for (int i = 0; i < r.samples_size() && i < kMaxEnsembleMembers; ++i) {
    const auto& values = r.samples(i).values();
    const std::string path = absl::StrCat("objective.robust.samples[", i, "].values");
    if (values.size() != r.parameters_size()) {
      e.push_back({path, absl::StrCat("has ", values.size(), " values for ",
                                      r.parameters_size(), " parameters (one each, in order)")});
      continue;
    }
    for (int j = 0; j < values.size(); ++j) {
      const auto& p = r.parameters(j);
      if (!(values[j] >= p.lo() && values[j] <= p.hi()))
        e.push_back({absl::StrCat(path, "[", j, "]"),
                     absl::StrCat("= ", values[j], " leaves ", p.name(), "'s range [", p.lo(),
                                  ", ", p.hi(), "]")});
    }
  }
}

}  // namespace

void ApplyRobustDefaults(gaitforge::v1::StudySpec* spec) {
  if (!spec->objective().has_robust()) return;
  auto* r = spec->mutable_objective()->mutable_robust();
  if (r->seed() == 0) r->set_seed(spec->seed());
  if (r->statistic().empty()) r->set_statistic("mean");
  if (!r->has_quantile()) r->set_quantile(0.25);
  if (!r->has_k()) r->set_k(1);
  if (!r->has_start_phases()) r->set_start_phases(1);
  const auto* info = core::FindObjective(spec->objective().name());
  if (r->numerics_size() == 1 && r->numerics(0) == "standard" && info != nullptr) {
    auto robot = core::RobotOfObjective(*info, spec->objective().robot(),
                                        spec->objective().robot_descriptor());
    if (robot.ok()) {  // else validation says why
      r->clear_numerics();
      for (const std::string& v : robots::StandardNumerics(**robot)) r->add_numerics(v);
    }
  }
  if (!r->has_members())
    r->set_members(std::max(1, r->numerics_size()) * std::max(1, r->start_phases()));
}

void ValidateRobust(const gaitforge::v1::StudySpec& spec, const core::ObjectiveInfo& info,
                    std::vector<FieldError>& e) {
  if (!spec.objective().has_robust()) return;
  const auto& r = spec.objective().robust();
  if (!info.robust) {
    e.push_back({"objective.robust", absl::StrCat(info.name, " takes no robust evaluation; "
                                                  "objectives that do: ", Objectives())});
    return;
  }
  if (r.members() < 1 || r.members() > kMaxEnsembleMembers)
    e.push_back({"objective.robust.members",
                 absl::StrCat("= ", r.members(), " is out of range [1, ", kMaxEnsembleMembers, "]")});
  if (r.start_phases() < 1 || r.start_phases() > kMaxStartPhases)
    e.push_back({"objective.robust.start_phases",
                 absl::StrCat("= ", r.start_phases(), " is out of range [1, ", kMaxStartPhases, "]")});
  if (r.statistic() != "mean" && r.statistic() != "quantile" && r.statistic() != "mean_minus_sd")
    e.push_back({"objective.robust.statistic",
                 absl::StrCat("'", r.statistic(), "' is not one of mean, quantile, mean_minus_sd")});
  if (!(r.quantile() > 0 && r.quantile() < 1))
    e.push_back({"objective.robust.quantile",
                 absl::StrCat("= ", r.quantile(), " must lie in (0, 1) (a lower quantile)")});
  if (!(r.k() >= 0 && r.k() <= kMaxK))
    e.push_back({"objective.robust.k",
                 absl::StrCat("= ", r.k(), " is out of range [0, ", kMaxK, "]")});
  auto robot = core::RobotOfObjective(info, spec.objective().robot(),
                                      spec.objective().robot_descriptor());
  if (!robot.ok()) return;  // the robot's own error is reported with objective.robot
  ValidateNumerics(r, **robot, e);
  ValidateSamples(spec, e);
  for (int i = 0; i < r.parameters_size(); ++i) {
    const auto& p = r.parameters(i);
    const std::string path = absl::StrCat("objective.robust.parameters[", i, "]");
    if (!std::isfinite(p.lo()) || !std::isfinite(p.hi()) || !(p.lo() <= p.hi()))
      e.push_back({path, absl::StrCat("needs finite lo <= hi; got lo = ", p.lo(), ", hi = ", p.hi())});
    else if (p.log() && !(p.lo() > 0))
      e.push_back({path + ".log", absl::StrCat("needs lo > 0 (sampled by its logarithm); got lo = ",
                                               p.lo())});
    else if (p.circular())
      e.push_back({path + ".circular", "an ensemble range is sampled, not searched: circular "
                                       "applies to bounds only"});
    else if (std::string bad = RangeError(**robot, p.name(), p.lo(), p.hi()); !bad.empty())
      e.push_back({path + ".name", bad});
  }
}

}  // namespace gaitforge::spec
