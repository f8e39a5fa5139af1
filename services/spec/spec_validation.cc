#include "services/spec/spec_validation.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "robots/registry.h"
#include "services/core/objective_catalog.h"
#include "services/spec/engine_kinds.h"
#include "services/spec/robust_validation.h"
#include "workers/effects/effects.h"

namespace gaitforge::spec {

using gaitforge::v1::StudySpec;

constexpr int kMaxGenerations = 100000;
constexpr int kMaxGenes = 1000;

void ApplyDefaults(StudySpec* spec) {
  if (spec->engine().empty()) spec->set_engine(EngineKinds().front().name);
  if (spec->name().empty()) spec->set_name("study");
  if (spec->bounds_size() == 0) {
    if (const auto* info = core::FindObjective(spec->objective().name())) {
      std::vector<core::GeneRange> space = info->default_space;
      if (info->uses_robot && !info->calibration) {
        auto robot = robots::ResolveRobot(spec->objective().robot(),
                                          spec->objective().robot_descriptor());
        if (robot.ok()) space = core::GeneSpaceOf(**robot);  // else Validate says why
      }
      for (const auto& g : space) {
        auto* b = spec->add_bounds();
        b->set_name(g.name);
        b->set_lo(g.lo);
        b->set_hi(g.hi);
        b->set_circular(g.circular);
      }
    }
  }
  for (int i = 0; i < spec->bounds_size(); ++i) {
    if (spec->bounds(i).name().empty()) spec->mutable_bounds(i)->set_name(absl::StrCat("x", i));
  }
  if (const EngineKind* k = FindEngineKind(spec->engine())) k->apply_defaults(spec);
  for (auto& c : *spec->mutable_constraints()) {
    if (!c.has_scale()) c.set_scale(1.0);
  }
  ApplyRobustDefaults(spec);
}

namespace {

// A calibration's genes must name the robot's calibratable parameters (or the objective's
// nuisance parameters): a misspelt name would otherwise make every member invalid.
void ValidateCalibrationGenes(const StudySpec& spec, const core::ObjectiveInfo& info,
                              const robots::RobotDescriptor& robot, std::vector<FieldError>& e) {
  std::vector<std::string> known = effects::FittableNames(robot);
  known.insert(known.end(), info.nuisance.begin(), info.nuisance.end());
  for (int i = 0; i < spec.bounds_size(); ++i) {
    const std::string& name = spec.bounds(i).name();
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    e.push_back({absl::StrCat("bounds[", i, "].name"),
                 absl::StrCat("'", name, "' is not a calibratable parameter of the ",
                              robot.name, "; nearest: ",
                              absl::StrJoin(robots::Nearest(name, known), ", "),
                              robots::FindRobot(robot.name) == &robot
                                  ? absl::StrCat(" (all: docs/calibration.md, or robots/",
                                                 robot.name,
                                                 "/robot.yaml's parameters marked calibrate "
                                                 "and its scales)")
                                  : " (all: the descriptor's parameters marked calibrate, its "
                                    "scales, and the effects docs/effects.md attaches to its "
                                    "parts)")});
  }
}

// Genes after the controller's (from `first` on) name the robot's parameters, within their
// ranges: a body searched together with its gait (paper 001's knee stiffness and friction).
void ValidateBodyGenes(const StudySpec& spec, int first, const robots::RobotDescriptor& d,
                       std::vector<FieldError>& e) {
  std::vector<std::string> known;
  for (const auto& p : d.parameters) known.push_back(p.name);
  for (int i = first; i < spec.bounds_size(); ++i) {
    const auto& b = spec.bounds(i);
    const robots::Parameter* p = d.FindParameter(b.name());
    if (p == nullptr) {
      e.push_back({absl::StrCat("bounds[", i, "].name"),
                   absl::StrCat("'", b.name(), "' is neither a gene of robot ", d.name,
                                "'s controller nor one of its parameters; nearest: ",
                                absl::StrJoin(robots::Nearest(b.name(), known), ", "))});
      continue;
    }
    for (double x : {b.lo(), b.hi()})
      if (std::string bad = p->Check(x); !bad.empty())
        e.push_back({absl::StrCat("bounds[", i, "]"), bad});
  }
}

// A robot-agnostic objective's robot must resolve to a generic model, and the genes must be
// its controller's, in order (a calibration's: its calibratable names).
// False when the robot itself is wrong: errors about the genes would only follow from it.
bool ValidateRobotGenes(const StudySpec& spec, const core::ObjectiveInfo& info,
                        std::vector<FieldError>& e) {
  const auto& o = spec.objective();
  if (o.robot().empty() && o.robot_descriptor().empty()) {
    e.push_back({"objective.robot", absl::StrCat("is required for ", o.name(),
                                                 ": a built-in robot's name (",
                                                 absl::StrJoin(robots::RobotNames(), ", "),
                                                 ") or a descriptor file's path")});
    return false;
  }
  auto robot = robots::ResolveRobot(o.robot(), o.robot_descriptor());
  if (!robot.ok()) {
    e.push_back({"objective.robot", std::string(robot.status().message())});
    return false;
  }
  const robots::RobotDescriptor& d = **robot;
  if (d.model != "generic") {
    // The robot's own model's objective of the same kind, from the catalog.
    std::string own;
    for (const auto& c : core::ObjectiveCatalog())
      if ((info.calibration ? c.calibrates : c.gait_robot) == d.name) own = c.name;
    e.push_back({"objective.robot",
                 absl::StrCat("robot '", d.name, "' has model '", d.model, "'; ", o.name(),
                              " simulates model: generic robots",
                              own.empty() ? "" : absl::StrCat(" (robot '", d.name, "': ", own, ")"))});
    return false;
  }
  if (info.calibration) {
    ValidateCalibrationGenes(spec, info, d, e);
    return true;
  }
  const auto& genes = d.controller.genes;
  if (spec.bounds_size() < static_cast<int>(genes.size())) {
    e.push_back({"bounds", absl::StrCat("has ", spec.bounds_size(), " genes; robot ", d.name,
                                        "'s controller has ", genes.size(),
                                        " (its parameters may follow them)")});
    return true;
  }
  for (int i = 0; i < static_cast<int>(genes.size()); ++i) {
    if (spec.bounds(i).name() == genes[i].name) continue;
    e.push_back({absl::StrCat("bounds[", i, "].name"),
                 absl::StrCat("'", spec.bounds(i).name(), "' must be '", genes[i].name,
                              "', gene ", i, " of robot ", d.name)});
  }
  ValidateBodyGenes(spec, static_cast<int>(genes.size()), d, e);
  return true;
}

// A circular mark belongs on a phase: a gene the robot's controller marks circular, over
// one whole cycle.
void ValidateCircular(const StudySpec& spec, const core::ObjectiveInfo* info,
                      std::vector<FieldError>& e) {
  std::shared_ptr<const robots::RobotDescriptor> robot;
  if (info != nullptr && !info->calibration)
    if (auto r = core::RobotOfObjective(*info, spec.objective().robot(),
                                        spec.objective().robot_descriptor());
        r.ok())
      robot = *r;
  for (int i = 0; i < spec.bounds_size(); ++i) {
    const auto& b = spec.bounds(i);
    if (!b.circular()) continue;
    const robots::Gene* gene = nullptr;
    if (robot)
      for (const auto& g : robot->controller.genes)
        if (g.name == b.name() && g.circular) gene = &g;
    const std::string path = absl::StrCat("bounds[", i, "].circular");
    if (gene == nullptr)
      e.push_back({path, absl::StrCat("'", b.name(), "' is not a phase",
                                      robot ? absl::StrCat(" of robot ", robot->name, "'s controller")
                                            : absl::StrCat(" (", spec.objective().name(),
                                                           " drives no robot's controller)"),
                                      "; only phase genes may be circular")});
    else if (b.hi() - b.lo() != gene->hi - gene->lo)
      e.push_back({path, absl::StrCat("needs '", b.name(), "' to span one whole cycle (hi - lo = ",
                                      gene->hi - gene->lo, "); got [", b.lo(), ", ", b.hi(), "]")});
  }
}

}  // namespace

namespace {

// A validation study before the coordinator resolves it (`validate` and no objective):
// only its own fields; the coordinator checks the rest against the study it names.
std::vector<FieldError> ValidateRequest(const v1::Validation& v) {
  std::vector<FieldError> e;
  if (v.study_id().empty())
    e.push_back({"validate.study_id", "is required: the robust study whose gaits are validated"});
  if (v.members() < 0 || v.members() > kMaxEnsembleMembers)
    e.push_back({"validate.members", absl::StrCat("= ", v.members(), " is out of range [0, ",
                                                  kMaxEnsembleMembers, "] (0: four times the study's)")});
  if (v.top() < 0)
    e.push_back({"validate.top", absl::StrCat("= ", v.top(), " must be >= 0 (0: every gait)")});
  return e;
}

}  // namespace

std::vector<FieldError> Validate(const StudySpec& spec) {
  if (spec.has_validate() && spec.objective().name().empty()) return ValidateRequest(spec.validate());
  std::vector<FieldError> e;
  auto add = [&](std::string path, std::string msg) { e.push_back({std::move(path), std::move(msg)}); };
  if (spec.name().size() > 128)
    add("name", absl::StrCat("is ", spec.name().size(), " characters long; at most 128 allowed"));
  const EngineKind* engine = FindEngineKind(spec.engine());
  if (engine == nullptr)
    add("engine", absl::StrCat("'", spec.engine(), "' is not an engine; allowed: ", EngineNames()));
  for (const EngineKind& k : EngineKinds()) {
    const auto* field = spec.GetDescriptor()->FindFieldByName(k.section);
    if (k.name != spec.engine() && spec.GetReflection()->HasField(spec, field))
      add(k.section, absl::StrCat("is set but the engine is '", spec.engine(), "'"));
  }
  if (spec.generations() < 1 || spec.generations() > kMaxGenerations)
    add("generations",
        absl::StrCat("= ", spec.generations(), " is out of range [1, ", kMaxGenerations, "]"));

  const auto* info = core::FindObjective(spec.objective().name());
  bool robot_ok = true;  // a wrong robot leaves the genes unknown: no errors about them
  if (spec.objective().name().empty()) {
    add("objective.name", absl::StrCat("is required; one of ", core::ObjectiveNames()));
  } else if (!info) {
    add("objective.name", absl::StrCat("'", spec.objective().name(),
                                       "' is not a known objective; one of ",
                                       core::ObjectiveNames()));
  } else {
    for (const auto& [name, value] : spec.objective().params()) {
      const core::ParamInfo* p = nullptr;
      for (const auto& q : info->params)
        if (q.name == name) p = &q;
      const std::string path = absl::StrCat("objective.params.", name);
      if (!p) {
        std::vector<std::string> known;
        for (const auto& q : info->params) known.push_back(q.name);
        add(path, absl::StrCat("is not a parameter of ", info->name, " (known: ",
                               known.empty() ? "none" : absl::StrJoin(known, ", "), ")"));
      } else if (!std::isfinite(value) || value < p->lo || value > p->hi) {
        add(path, absl::StrCat("= ", value, " is out of range [", p->lo, ", ", p->hi, "] (",
                               p->meaning, ")"));
      } else if (p->integer && value != std::floor(value)) {
        add(path, absl::StrCat("= ", value, " must be a whole number (", p->meaning, ")"));
      }
    }
    for (const auto& [name, value] : spec.objective().options()) {
      const std::string path = absl::StrCat("objective.options.", name);
      const std::vector<std::string>* allowed = nullptr;
      for (const auto& [n, values] : info->options)
        if (n == name) allowed = &values;
      if (!allowed) {
        std::vector<std::string> known;
        for (const auto& [n, values] : info->options) known.push_back(n);
        add(path, absl::StrCat("is not an option of ", info->name, " (known: ",
                               known.empty() ? "none" : absl::StrJoin(known, ", "), ")"));
      } else if (!allowed->empty() &&
                 std::find(allowed->begin(), allowed->end(), value) == allowed->end()) {
        add(path, absl::StrCat("'", value, "' is not one of ", absl::StrJoin(*allowed, ", ")));
      }
    }
    if (info->needs_recordings && spec.objective().recordings_size() == 0)
      add("objective.recordings",
          absl::StrCat("needs at least one recording for ", info->name));
    if (!info->needs_recordings && (spec.objective().recordings_size() > 0 ||
                                    spec.objective().held_out_size() > 0))
      add("objective.recordings", absl::StrCat(info->name, " takes no recordings"));
    for (int i = 0; i < spec.objective().recordings_size(); ++i)
      if (spec.objective().recordings(i).empty())
        add(absl::StrCat("objective.recordings[", i, "]"), "is empty");
    for (int i = 0; i < spec.objective().held_out_size(); ++i)
      if (spec.objective().held_out(i).empty())
        add(absl::StrCat("objective.held_out[", i, "]"), "is empty");
    if (const auto* robot = robots::FindRobot(info->calibrates))
      ValidateCalibrationGenes(spec, *info, *robot, e);
    if (info->uses_robot) robot_ok = ValidateRobotGenes(spec, *info, e);
    ValidateRobust(spec, *info, e);
    if (info->required_genes > 0 && spec.bounds_size() != info->required_genes)
      add("bounds", absl::StrCat("has ", spec.bounds_size(), " genes; ", info->name,
                                 " needs exactly ", info->required_genes));
  }

  if (robot_ok && (spec.bounds_size() == 0 || spec.bounds_size() > kMaxGenes))
    add("bounds", absl::StrCat("has ", spec.bounds_size(), " genes; allowed 1..", kMaxGenes));
  std::set<std::string> names;
  for (int i = 0; i < spec.bounds_size(); ++i) {
    const auto& b = spec.bounds(i);
    const std::string path = absl::StrCat("bounds[", i, "]");
    if (!std::isfinite(b.lo()) || !std::isfinite(b.hi()) || !(b.lo() < b.hi()))
      add(path, absl::StrCat("needs finite lo < hi; got lo = ", b.lo(), ", hi = ", b.hi()));
    if (!names.insert(b.name()).second)
      add(absl::StrCat(path, ".name"), absl::StrCat("'", b.name(), "' appears twice"));
    if (b.log() && !(b.lo() > 0))
      add(path + ".log", absl::StrCat("needs lo > 0 (the gene is searched by its logarithm); got "
                                      "lo = ", b.lo()));
    if (b.log() && b.circular())
      add(path + ".log", "and circular exclude each other: a phase is searched on its circle");
  }

  ValidateCircular(spec, info, e);
  if (engine != nullptr) engine->validate(spec, e);
  for (int i = 0; i < spec.constraints_size(); ++i) {
    const auto& c = spec.constraints(i);
    const std::string path = absl::StrCat("constraints[", i, "]");
    if (c.metric().empty()) add(path + ".metric", "is required (a metric the objective returns)");
    if (!c.has_min() && !c.has_max()) add(path, "needs min, max or both");
    if (c.has_min() && c.has_max() && !(c.min() <= c.max()))
      add(path, absl::StrCat("needs min <= max; got min = ", c.min(), ", max = ", c.max()));
    if (!(c.scale() > 0)) add(path + ".scale", absl::StrCat("= ", c.scale(), " must be > 0"));
  }
  return e;
}

namespace {

// Errors about integers the loader clamped show the text as written, and a clamped
// integer no rule refused (every spec integer has a narrower range) is still an error.
std::vector<FieldError> WithWrittenIntegers(std::vector<FieldError> errors,
                                            const LoadedSpec& where) {
  for (const auto& [path, text] : where.clamped) {
    bool reported = false;
    for (auto& err : errors) {
      if (err.path != path) continue;
      reported = true;
      if (err.message.rfind("= ", 0) == 0)
        err.message = absl::StrCat("= ", text, err.message.substr(err.message.find(' ', 2)));
    }
    if (!reported) errors.push_back({path, absl::StrCat("= ", text, " is out of range")});
  }
  return errors;
}

}  // namespace

absl::Status ValidationStatus(const std::vector<FieldError>& given, const LoadedSpec* where) {
  const std::vector<FieldError> errors = where ? WithWrittenIntegers(given, *where) : given;
  if (errors.empty()) return absl::OkStatus();
  std::vector<std::string> lines;
  for (const auto& err : errors) {
    std::string prefix;
    if (where) {
      // The nearest enclosing path that was written in the file.
      std::string p = err.path;
      for (;;) {
        auto it = where->marks.find(p);
        if (it != where->marks.end()) {
          prefix = absl::StrCat(where->source, ":", it->second.line, ":", it->second.column, ": ");
          break;
        }
        const size_t cut = p.find_last_of(".[");
        if (cut == std::string::npos) {
          prefix = absl::StrCat(where->source, ": ");
          break;
        }
        p = p.substr(0, cut);
      }
    }
    lines.push_back(absl::StrCat(prefix, "field '", err.path, "' ", err.message));
  }
  return absl::InvalidArgumentError(absl::StrJoin(lines, "\n"));
}

}  // namespace gaitforge::spec
