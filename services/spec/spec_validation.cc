#include "services/spec/spec_validation.h"

#include <cmath>
#include <string>
#include <algorithm>
#include <set>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "robots/registry.h"
#include "services/core/objective_catalog.h"

namespace gaitforge::spec {

using gaitforge::v1::StudySpec;

constexpr int kMaxPopulation = 100000;
constexpr int kMaxGenerations = 100000;
constexpr int kMaxGenes = 1000;

void ApplyDefaults(StudySpec* spec) {
  if (spec->engine().empty()) spec->set_engine("ga");
  if (spec->name().empty()) spec->set_name("study");
  if (spec->bounds_size() == 0) {
    if (const auto* info = core::FindObjective(spec->objective().name())) {
      std::vector<core::GeneRange> space = info->default_space;
      if (info->uses_robot) {
        auto robot = robots::ResolveRobot(spec->objective().robot(),
                                          spec->objective().robot_descriptor());
        if (robot.ok()) space = core::GeneSpaceOf(**robot);  // else Validate says why
      }
      for (const auto& g : space) {
        auto* b = spec->add_bounds();
        b->set_name(g.name);
        b->set_lo(g.lo);
        b->set_hi(g.hi);
      }
    }
  }
  for (int i = 0; i < spec->bounds_size(); ++i) {
    if (spec->bounds(i).name().empty()) spec->mutable_bounds(i)->set_name(absl::StrCat("x", i));
  }
  if (spec->engine() == "ga") {
    auto* ga = spec->mutable_ga();
    if (!ga->has_elite()) ga->set_elite(10);
    if (!ga->has_mutation_rate()) ga->set_mutation_rate(0.10);
  } else if (spec->engine() == "cmaes") {
    auto* c = spec->mutable_cmaes();
    if (!c->has_sigma0()) c->set_sigma0(0.3);
    if (!c->has_max_evaluations()) c->set_max_evaluations(100000);
    if (c->restarts().empty()) c->set_restarts("ipop");
    if (!c->has_max_restarts()) c->set_max_restarts(9);
    if (!c->has_tolfun()) c->set_tolfun(1e-12);
    if (!c->has_tolx()) c->set_tolx(1e-12);
  } else if (spec->engine() == "sweep") {
    auto* w = spec->mutable_sweep();
    if (w->points_per_axis_size() == 0) w->add_points_per_axis(5);
    if (!w->has_top_k()) w->set_top_k(3);
    if (!w->has_nm_max_iterations()) w->set_nm_max_iterations(200);
    if (!w->has_nm_tolerance()) w->set_nm_tolerance(1e-8);
    if (!w->has_max_evaluations()) w->set_max_evaluations(0);
  }
  for (auto& c : *spec->mutable_constraints()) {
    if (!c.has_scale()) c.set_scale(1.0);
  }
}

namespace {

// A calibration's genes must name the robot's calibratable parameters (or the objective's
// nuisance parameters): a misspelt name would otherwise make every member invalid.
void ValidateCalibrationGenes(const StudySpec& spec, const core::ObjectiveInfo& info,
                              std::vector<FieldError>& e) {
  const robots::RobotDescriptor* robot = robots::FindRobot(info.calibrates);
  if (robot == nullptr) return;
  std::vector<std::string> known = robot->CalibratableNames();
  known.insert(known.end(), info.nuisance.begin(), info.nuisance.end());
  for (int i = 0; i < spec.bounds_size(); ++i) {
    const std::string& name = spec.bounds(i).name();
    if (std::find(known.begin(), known.end(), name) != known.end()) continue;
    e.push_back({absl::StrCat("bounds[", i, "].name"),
                 absl::StrCat("'", name, "' is not a calibratable parameter of the ",
                              robot->name, "; nearest: ",
                              absl::StrJoin(robots::Nearest(name, known), ", "),
                              " (all: docs/calibration.md, or robots/", robot->name,
                              "/robot.yaml's parameters marked calibrate and its scales)")});
  }
}

// A robot-agnostic objective's robot must resolve to a generic model, and the genes must be
// its controller's, in order.
// False when the robot itself is wrong: errors about the genes would only follow from it.
bool ValidateRobotGenes(const StudySpec& spec, std::vector<FieldError>& e) {
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
    e.push_back({"objective.robot",
                 absl::StrCat("robot '", d.name, "' has model '", d.model, "'; ", o.name(),
                              " simulates model: generic robots (the caterpillar: "
                              "caterpillar.distance)")});
    return false;
  }
  const auto& genes = d.controller.genes;
  if (spec.bounds_size() != static_cast<int>(genes.size())) {
    e.push_back({"bounds", absl::StrCat("has ", spec.bounds_size(), " genes; robot ", d.name,
                                        "'s controller has ", genes.size())});
    return true;
  }
  for (int i = 0; i < spec.bounds_size(); ++i) {
    if (spec.bounds(i).name() == genes[i].name) continue;
    e.push_back({absl::StrCat("bounds[", i, "].name"),
                 absl::StrCat("'", spec.bounds(i).name(), "' must be '", genes[i].name,
                              "', gene ", i, " of robot ", d.name)});
  }
  return true;
}

void ValidateCmaes(const StudySpec& spec, std::vector<FieldError>& e) {
  const auto& c = spec.cmaes();
  auto add = [&](std::string path, std::string msg) { e.push_back({std::move(path), std::move(msg)}); };
  if (spec.population() != 0 && (spec.population() < 4 || spec.population() > 100000))
    add("population", absl::StrCat("= ", spec.population(),
                                   " is out of range: 0 (default lambda) or [4, 100000]"));
  const bool population_ok =
      spec.population() == 0 || (spec.population() >= 4 && spec.population() <= 100000);
  const int n = spec.bounds_size();
  const int lambda = spec.population() != 0
                         ? spec.population()
                         : 4 + static_cast<int>(std::floor(3 * std::log(std::max(n, 1))));
  if (population_ok && c.max_evaluations() < lambda)
    add("cmaes.max_evaluations",
        absl::StrCat("= ", c.max_evaluations(), " is below one generation (lambda = ", lambda,
                     ")"));
  if (!(c.sigma0() > 0 && c.sigma0() <= 1))
    add("cmaes.sigma0", absl::StrCat("= ", c.sigma0(), " is out of range (0, 1]"));
  if (c.mean0_size() != 0 && c.mean0_size() != spec.bounds_size())
    add("cmaes.mean0", absl::StrCat("has ", c.mean0_size(), " values; the space has ",
                                    spec.bounds_size(), " genes"));
  for (int i = 0; i < c.mean0_size() && c.mean0_size() == spec.bounds_size(); ++i) {
    const auto& b = spec.bounds(i);
    if (!(c.mean0(i) >= b.lo() && c.mean0(i) <= b.hi()))
      add(absl::StrCat("cmaes.mean0[", i, "]"),
          absl::StrCat("= ", c.mean0(i), " is outside bounds [", b.lo(), ", ", b.hi(), "]"));
  }
  if (c.max_evaluations() < 1 || c.max_evaluations() > 1000000000000LL)
    add("cmaes.max_evaluations",
        absl::StrCat("= ", c.max_evaluations(), " is out of range [1, 1e12]"));
  if (c.restarts() != "none" && c.restarts() != "ipop" && c.restarts() != "bipop")
    add("cmaes.restarts", absl::StrCat("'", c.restarts(), "' is not one of none, ipop, bipop"));
  if (c.max_restarts() < 0 || c.max_restarts() > 20)
    add("cmaes.max_restarts", absl::StrCat("= ", c.max_restarts(), " is out of range [0, 20]"));
  if (!(c.tolfun() >= 0)) add("cmaes.tolfun", absl::StrCat("= ", c.tolfun(), " must be >= 0"));
  if (!(c.tolx() >= 0)) add("cmaes.tolx", absl::StrCat("= ", c.tolx(), " must be >= 0"));
}

void ValidateSweep(const StudySpec& spec, std::vector<FieldError>& e) {
  const auto& w = spec.sweep();
  auto add = [&](std::string path, std::string msg) { e.push_back({std::move(path), std::move(msg)}); };
  if (spec.population() < 0 || spec.population() > 10000000)
    add("population", absl::StrCat("= ", spec.population(),
                                   " is out of range: 0 (whole grid) or [1, 1e7] grid points "
                                   "per generation"));
  if (w.points_per_axis_size() != 1 && w.points_per_axis_size() != spec.bounds_size())
    add("sweep.points_per_axis",
        absl::StrCat("has ", w.points_per_axis_size(), " values; give 1 or one per gene (",
                     spec.bounds_size(), ")"));
  double grid = 1;
  for (int i = 0; i < w.points_per_axis_size(); ++i) {
    const int p = w.points_per_axis(i);
    if (p < 1 || p > 1000)
      add(absl::StrCat("sweep.points_per_axis[", i, "]"),
          absl::StrCat("= ", p, " is out of range [1, 1000]"));
    grid *= w.points_per_axis_size() == 1 ? std::pow(p, spec.bounds_size()) : p;
  }
  if (grid > 1e7)
    add("sweep.points_per_axis", absl::StrCat("make a grid of ", grid, " points; at most 1e7"));
  if (w.top_k() < 1 || w.top_k() > 1000 || (grid >= 1 && w.top_k() > grid))
    add("sweep.top_k", absl::StrCat("= ", w.top_k(), " is out of range [1, min(1000, grid size = ",
                                    grid, ")]"));
  const double first_batch = spec.population() > 0 ? std::min<double>(spec.population(), grid) : grid;
  const bool population_ok = spec.population() >= 0 && spec.population() <= 10000000;
  if (population_ok && w.max_evaluations() > 0 && w.max_evaluations() < first_batch)
    add("sweep.max_evaluations", absl::StrCat("= ", w.max_evaluations(),
                                              " is below the first grid batch (", first_batch, ")"));
  if (w.nm_max_iterations() < 0 || w.nm_max_iterations() > 1000000)
    add("sweep.nm_max_iterations",
        absl::StrCat("= ", w.nm_max_iterations(), " is out of range [0, 1e6]"));
  if (!(w.nm_tolerance() >= 0 && w.nm_tolerance() < 1))
    add("sweep.nm_tolerance", absl::StrCat("= ", w.nm_tolerance(), " is out of range [0, 1)"));
  if (w.max_evaluations() < 0)
    add("sweep.max_evaluations", absl::StrCat("= ", w.max_evaluations(), " must be >= 0"));
}

}  // namespace

std::vector<FieldError> Validate(const StudySpec& spec) {
  std::vector<FieldError> e;
  auto add = [&](std::string path, std::string msg) { e.push_back({std::move(path), std::move(msg)}); };
  if (spec.name().size() > 128)
    add("name", absl::StrCat("is ", spec.name().size(), " characters long; at most 128 allowed"));
  const bool known_engine =
      spec.engine() == "ga" || spec.engine() == "cmaes" || spec.engine() == "sweep";
  if (!known_engine)
    add("engine", absl::StrCat("'", spec.engine(), "' is not an engine; allowed: ga, cmaes, sweep"));
  if (spec.engine() == "ga" && (spec.population() < 2 || spec.population() > kMaxPopulation))
    add("population",
        absl::StrCat("= ", spec.population(), " is out of range [2, ", kMaxPopulation, "]"));
  if (spec.engine() != "ga" && spec.has_ga())
    add("ga", absl::StrCat("is set but the engine is '", spec.engine(), "'"));
  if (spec.engine() != "cmaes" && spec.has_cmaes())
    add("cmaes", absl::StrCat("is set but the engine is '", spec.engine(), "'"));
  if (spec.engine() != "sweep" && spec.has_sweep())
    add("sweep", absl::StrCat("is set but the engine is '", spec.engine(), "'"));
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
    if (!info->calibrates.empty()) ValidateCalibrationGenes(spec, *info, e);
    if (info->uses_robot) robot_ok = ValidateRobotGenes(spec, e);
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
  }

  if (spec.engine() == "ga") {
    const auto& ga = spec.ga();
    // Against a bad population the elite's range means nothing: that error is reported.
    const bool population_ok = spec.population() >= 2 && spec.population() <= kMaxPopulation;
    if (population_ok && (ga.elite() < 0 || ga.elite() >= spec.population()))
      add("ga.elite", absl::StrCat("= ", ga.elite(), " is out of range [0, population - 1 = ",
                                   spec.population() - 1, "]"));
    if (!std::isfinite(ga.mutation_rate()) || ga.mutation_rate() < 0 || ga.mutation_rate() > 1)
      add("ga.mutation_rate", absl::StrCat("= ", ga.mutation_rate(), " is out of range [0, 1]"));
  }
  if (spec.engine() == "cmaes") ValidateCmaes(spec, e);
  if (spec.engine() == "sweep") ValidateSweep(spec, e);
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
