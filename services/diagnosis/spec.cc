// The diagnosis spec's rules: its defaults and the checks that name a bad field.
#include "services/diagnosis/spec.h"

#include <algorithm>
#include <cmath>

#include <string>
#include <vector>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "services/core/objective_catalog.h"
#include "robots/registry.h"
#include "services/diagnosis/fits.h"
#include "workers/effects/effects.h"

namespace gaitforge::diagnosis {
namespace {

// The index of the first base parameter that `e` also fits, or -1.
int SharedWithBase(const effects::EffectInfo& e, const v1::DiagnosisSpec& d) {
  for (int i = 0; i < d.base_parameters_size(); ++i)
    for (const auto& p : e.params)
      if (p.name == d.base_parameters(i).name()) return i;
  return -1;
}

}  // namespace

// params: the calibration objective's comparison params, by its catalog, but timestep_ms
// (its own field).
absl::Status CheckParams(const v1::DiagnosisSpec& d) {
  const core::ObjectiveInfo* info = core::FindObjective(CalibrationObjective(d));
  for (const auto& [name, value] : d.params()) {
    const core::ParamInfo* p = nullptr;
    std::vector<std::string> known;
    for (const auto& q : info ? info->params : std::vector<core::ParamInfo>{}) {
      if (q.name == "timestep_ms") continue;
      known.push_back(q.name);
      if (q.name == name) p = &q;
    }
    if (!p)
      return absl::InvalidArgumentError(absl::StrCat("field 'params." , name, "': not a param of the comparison (known: ",
                                                     absl::StrJoin(known, ", "), ")"));
    if (!(value >= p->lo && value <= p->hi) || (p->integer && value != std::round(value)))
      return absl::InvalidArgumentError(absl::StrCat("field 'params.", name, "': ", value,
                                                     " is out of range [", p->lo, ", ", p->hi, "]",
                                                     p->integer ? ", whole" : ""));
  }
  return absl::OkStatus();
}

// The diagnosis's own step must leave every numeric variant's step (fits.h) inside the
// robot's simulation.timestep_s range: otherwise the first weighting fails minutes in.
absl::Status CheckTimestep(const v1::DiagnosisSpec& d) {
  auto robot = RobotOf(d);
  if (!d.has_timestep_ms() || !robot.ok()) return absl::OkStatus();
  const robots::Parameter* h = (*robot)->FindParameter(kTimestepParam);
  if (h == nullptr) return absl::OkStatus();
  const std::string prefix = std::string(kTimestepParam) + "=";
  double largest = 0, smallest = INFINITY;
  for (const std::string& v : NumericVariants(d)) {
    if (v.rfind(prefix, 0) != 0) continue;
    largest = std::max(largest, std::stod(v.substr(prefix.size())));
    smallest = std::min(smallest, std::stod(v.substr(prefix.size())));
  }
  if (largest <= h->hi && smallest >= h->lo) return absl::OkStatus();
  const double ms = d.timestep_ms();
  return absl::InvalidArgumentError(absl::StrCat(
      "field 'timestep_ms': ", ms, " ms puts the numeric variants' steps at ", 1e3 * smallest,
      " to ", 1e3 * largest, " ms, outside ", (*robot)->name, "'s ", kTimestepParam, " range [",
      1e3 * h->lo, ", ", 1e3 * h->hi, "] ms; allowed here: ", ms * h->lo / smallest, " to ",
      ms * h->hi / largest, " ms"));
}

absl::Status Validate(const v1::DiagnosisSpec& d) {
  if (d.training_size() == 0)
    return absl::InvalidArgumentError("field 'training': at least one recording is required");
  if (d.held_out_size() == 0)
    return absl::InvalidArgumentError(
        "field 'held_out': at least one recording is required (decisions rest on it)");
  for (int h = 0; h < d.held_out_size(); ++h)
    for (int t = 0; t < d.training_size(); ++t)
      if (d.held_out(h) == d.training(t))
        return absl::InvalidArgumentError(absl::StrCat(
            "field 'held_out[", h, "]': '", d.held_out(h), "' is also training[", t,
            "]: a held-out recording must be one the fits never saw (else the decision "
            "rests on data the model was fitted to)"));
  if (d.robot().empty())
    return absl::InvalidArgumentError(
        "field 'robot': required: the robot the recordings are of, a built-in name or a "
        "descriptor file (left out, it is read from the first training recording's sidecar)");
  auto robot = RobotOf(d);
  if (!robot.ok() && !d.robot_descriptor().empty())
    return absl::InvalidArgumentError(absl::StrCat("field 'robot': ", robot.status().message()));
  if (CalibrationObjective(d).empty()) {
    std::vector<std::string> known;
    for (const auto& o : core::ObjectiveCatalog())
      if (!o.calibrates.empty()) known.push_back(o.calibrates);
    for (const std::string& name : robots::RobotNames())
      if (robots::Robot(name).model == "generic" &&
          std::find(known.begin(), known.end(), name) == known.end())
        known.push_back(name);
    return absl::InvalidArgumentError(absl::StrCat(
        "field 'robot': '", d.robot(), "' is not a robot gaitforge can diagnose (built in: ",
        absl::StrJoin(known, ", "),
        "; or a descriptor file of a robot on the generic builder, docs/robots.md)"));
  }
  for (const auto& suspect : (*robot)->suspects)
    if (effects::FindEffect(suspect.id))
      return absl::InvalidArgumentError(absl::StrCat(
          suspect.mark.ToString(), ": suspects.", suspect.id, ": '", suspect.id,
          "' is an effect of the catalog (docs/effects.md); give the robot's suspect its own id"));
  for (const auto& r : (*robot)->ruled_out)
    if (!effects::FindEffect(r.id))
      return absl::InvalidArgumentError(absl::StrCat(
          r.mark.ToString(), ": ruled_out.", r.id, ": '", r.id,
          "' is not an effect of the catalog (docs/effects.md lists them)"));
  if (d.candidates_size() == 0)  // Defaults fills in every effect that applies
    return absl::InvalidArgumentError(absl::StrCat(
        "field 'candidates': none to fit: no effect of the catalog applies to ", (*robot)->name,
        " beside what base_parameters fits already; a diagnosis needs at least one candidate "
        "(fit fewer base parameters, or give the robot suspects: docs/robots.md)"));
  for (int i = 0; i < d.candidates_size(); ++i) {
    const auto e = effects::FindEffect(d.candidates(i), **robot);
    if (!e || e->params.empty())
      return absl::InvalidArgumentError(absl::StrCat(
          "field 'candidates[", i, "]': '", d.candidates(i),
          "' is not a fittable effect (docs/effects.md lists them) or a suspect of ",
          (*robot)->name));
    if (std::string why = effects::WhyNotApplicable(*e, **robot); !why.empty())
      return absl::InvalidArgumentError(absl::StrCat("field 'candidates[", i, "]': '",
                                                     d.candidates(i), "' cannot be fitted on ",
                                                     (*robot)->name, ": ", why));
    if (int b = SharedWithBase(*e, d); b >= 0)
      return absl::InvalidArgumentError(absl::StrCat(
          "field 'candidates[", i, "]': '", d.candidates(i), "' fits ",
          d.base_parameters(b).name(), ", which base_parameters[", b,
          "] fits in every study already; leave one of them out"));
  }
  for (int i = 0; i < d.base_parameters_size(); ++i) {
    const auto& b = d.base_parameters(i);
    if (b.name().empty() || !(b.lo() < b.hi()))
      return absl::InvalidArgumentError(absl::StrCat(
          "field 'base_parameters[", i, "]': needs a name and lo < hi"));
  }
  if (d.time_offset_range_s() < 0 || d.time_offset_range_s() > 1)
    return absl::InvalidArgumentError("field 'time_offset_range_s': out of range [0, 1] s");
  if (d.base_parameters_size() == 0 && d.time_offset_range_s() == 0)
    return absl::InvalidArgumentError(
        "fields 'base_parameters' and 'time_offset_range_s': the baseline would fit nothing; "
        "name an uncertain parameter or let the time offset be fitted (> 0 s)");
  if (d.screening_evaluations() < 8 || d.full_evaluations() < 8)
    return absl::InvalidArgumentError(
        "fields 'screening_evaluations' and 'full_evaluations': at least 8");
  if (d.pair_evaluations() < 8)
    return absl::InvalidArgumentError(absl::StrCat("field 'pair_evaluations': ",
                                                   d.pair_evaluations(), " is below 8"));
  if (d.top() < 1 || d.top() > 20) return absl::InvalidArgumentError("field 'top': out of range [1, 20]");
  if (!(d.screening_tie() >= 0 && d.screening_tie() <= 0.2))
    return absl::InvalidArgumentError("field 'screening_tie': out of range [0, 0.2]");
  if (d.error() != "shape" && d.error() != "pointwise" && d.error() != "stats" &&
      d.error() != "acceleration")
    return absl::InvalidArgumentError("field 'error': one of shape, pointwise, stats, acceleration");
  if (absl::Status s = CheckParams(d); !s.ok()) return s;
  if (d.structure() != "off" && d.structure() != "first" && d.structure() != "joint")
    return absl::InvalidArgumentError(absl::StrCat("field 'structure': '", d.structure(),
                                                   "' is not one of off, first, joint"));
  if (d.numerics() != "off" && d.numerics() != "first")
    return absl::InvalidArgumentError(absl::StrCat("field 'numerics': '", d.numerics(),
                                                   "' is not one of off, first"));
  if (d.has_timestep_ms() && !(d.timestep_ms() >= 0.05 && d.timestep_ms() <= 2))
    return absl::InvalidArgumentError(absl::StrCat("field 'timestep_ms': ", d.timestep_ms(),
                                                   " is out of range [0.05, 2] ms"));
  if (absl::Status s = CheckTimestep(d); !s.ok()) return s;
  if (d.weighting() != "equal" && d.weighting() != "floor" && d.weighting() != "pooled")
    return absl::InvalidArgumentError(absl::StrCat("field 'weighting': '", d.weighting(),
                                                   "' is not one of equal, floor, pooled"));
  return absl::OkStatus();
}

void Defaults(v1::DiagnosisSpec* d) {
  if (d->name().empty()) d->set_name("diagnosis");
  if (!d->has_time_offset_range_s()) d->set_time_offset_range_s(0.05);
  if (!d->has_screening_evaluations()) d->set_screening_evaluations(120);
  if (!d->has_full_evaluations()) d->set_full_evaluations(480);
  if (!d->has_pair_evaluations()) d->set_pair_evaluations(std::max(8, d->full_evaluations() / 2));
  if (!d->has_top()) d->set_top(3);
  if (!d->has_screening_tie()) d->set_screening_tie(0);
  if (!d->has_try_pairs()) d->set_try_pairs(true);
  if (d->error().empty()) d->set_error("shape");
  if (d->weighting().empty()) d->set_weighting("floor");
  if (d->structure().empty()) d->set_structure("off");
  if (d->numerics().empty()) d->set_numerics("off");
  if (!d->has_margin()) d->set_margin(10);
  auto robot = RobotOf(*d);
  if (d->candidates_size() == 0 && robot.ok())
    for (const auto& e : effects::EffectsFor(**robot))
      if (effects::WhyNotApplicable(e, **robot).empty() && SharedWithBase(e, *d) < 0)
        d->add_candidates(e.id);
}

}  // namespace gaitforge::diagnosis
