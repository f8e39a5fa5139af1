#include "services/spec/spec_validation.h"

#include <cmath>
#include <set>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
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
      for (const auto& g : info->default_space) {
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
  }
}

std::vector<FieldError> Validate(const StudySpec& spec) {
  std::vector<FieldError> e;
  auto add = [&](std::string path, std::string msg) { e.push_back({std::move(path), std::move(msg)}); };
  if (spec.name().size() > 128)
    add("name", absl::StrCat("is ", spec.name().size(), " characters long; at most 128 allowed"));
  if (spec.engine() != "ga")
    add("engine", absl::StrCat("'", spec.engine(), "' is not an engine; allowed: ga"));
  if (spec.population() < 2 || spec.population() > kMaxPopulation)
    add("population",
        absl::StrCat("= ", spec.population(), " is out of range [2, ", kMaxPopulation, "]"));
  if (spec.generations() < 1 || spec.generations() > kMaxGenerations)
    add("generations",
        absl::StrCat("= ", spec.generations(), " is out of range [1, ", kMaxGenerations, "]"));

  const auto* info = core::FindObjective(spec.objective().name());
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
      }
    }
    if (info->required_genes > 0 && spec.bounds_size() != info->required_genes)
      add("bounds", absl::StrCat("has ", spec.bounds_size(), " genes; ", info->name,
                                 " needs exactly ", info->required_genes));
  }

  if (spec.bounds_size() == 0 || spec.bounds_size() > kMaxGenes)
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
    if (ga.elite() < 0 || ga.elite() >= spec.population())
      add("ga.elite", absl::StrCat("= ", ga.elite(), " is out of range [0, population - 1 = ",
                                   spec.population() - 1, "]"));
    if (!std::isfinite(ga.mutation_rate()) || ga.mutation_rate() < 0 || ga.mutation_rate() > 1)
      add("ga.mutation_rate", absl::StrCat("= ", ga.mutation_rate(), " is out of range [0, 1]"));
  }
  return e;
}

absl::Status ValidationStatus(const std::vector<FieldError>& errors, const LoadedSpec* where) {
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
