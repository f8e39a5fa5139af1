#include "services/spec/validation_spec.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "services/spec/robust_validation.h"

namespace gaitforge::spec {
namespace {

constexpr int kMembersPerStudyMember = 4;

// Why gait `i` does not fit the study's bounds; empty when it does.
std::string GaitError(const v1::StudySpec& study, const v1::Gait& gait, int i) {
  if (gait.genes_size() != study.bounds_size())
    return absl::StrCat("gait ", i + 1, " has ", gait.genes_size(),
                        " genes; the study's space has ", study.bounds_size());
  for (int j = 0; j < study.bounds_size(); ++j) {
    const auto& b = study.bounds(j);
    if (!(gait.genes(j) >= b.lo() && gait.genes(j) <= b.hi()))
      return absl::StrCat("gait ", i + 1, ": gene ", b.name(), " = ", gait.genes(j),
                          " is outside its bounds [", b.lo(), ", ", b.hi(), "]");
  }
  return "";
}

// The factor `gait`: level i sets every gene to gait i's.
v1::SweepFactor GaitFactor(const v1::StudySpec& study, const v1::Validation& request) {
  v1::SweepFactor f;
  f.set_name("gait");
  for (int i = 0; i < request.gaits_size(); ++i) f.add_levels(absl::StrCat(i + 1));
  for (int j = 0; j < study.bounds_size(); ++j) {
    auto* g = f.add_genes();
    g->set_gene(study.bounds(j).name());
    for (const auto& gait : request.gaits()) g->add_values(gait.genes(j));
  }
  return f;
}

// The seed the study's ensemble was drawn from.
uint64_t OwnSeed(const v1::StudySpec& study) {
  const uint64_t own = study.objective().robust().seed();
  return own != 0 ? own : study.seed();
}

// The members and seed a request resolves to (0: the defaults).
int ValidationMembers(const v1::StudySpec& study, int members) {
  if (members > 0) return members;
  return std::min(kMaxEnsembleMembers,
                  kMembersPerStudyMember * std::max(1, study.objective().robust().members()));
}

uint64_t ValidationSeed(const v1::StudySpec& study, uint64_t seed) {
  if (seed != 0) return seed;
  const uint64_t next = OwnSeed(study) + 1;
  return next != 0 ? next : 1;  // 0 would mean "the study's seed"
}

}  // namespace

absl::Status Validatable(const v1::StudySpec& study, const std::string& id) {
  if (study.objective().has_robust()) return absl::OkStatus();
  return absl::InvalidArgumentError(absl::StrCat(
      "study ", id, " has no objective.robust: its fitness is one evaluation of the model, "
      "with no ensemble to draw afresh"));
}

absl::StatusOr<v1::StudySpec> ValidationSpec(const v1::StudySpec& study,
                                             const v1::Validation& request) {
  if (auto s = Validatable(study, request.study_id()); !s.ok()) return s;
  if (request.gaits().empty()) return absl::InvalidArgumentError("no gaits to validate");
  for (int i = 0; i < request.gaits_size(); ++i)
    if (std::string bad = GaitError(study, request.gaits(i), i); !bad.empty())
      return absl::InvalidArgumentError(bad);
  const int members = ValidationMembers(study, request.members());
  if (members < 1 || members > kMaxEnsembleMembers)
    return absl::InvalidArgumentError(absl::StrCat(
        "members ", members, " is out of range [1, ", kMaxEnsembleMembers, "]"));
  const uint64_t seed = ValidationSeed(study, request.seed());
  if (seed == OwnSeed(study))
    return absl::InvalidArgumentError(absl::StrCat(
        "seed ", seed, " is the study's own ensemble seed: its members are those the study "
        "selected on, so the validation would repeat its predictions"));
  v1::StudySpec out;
  out.set_name(std::string(study.name()).substr(0, 100) + "-validation");
  out.set_seed(study.seed());
  out.set_engine("sweep");
  out.set_population(0);  // the whole design in one generation
  out.set_generations(1);
  *out.mutable_objective() = study.objective();
  // The stored objective holds what a fit resolved to; resolving it again would repeat it.
  out.mutable_objective()->clear_from_calibration();
  out.mutable_objective()->clear_from_diagnosis();
  // Its samples stay: the fresh seed takes other members from the same pool.
  out.mutable_objective()->mutable_robust()->clear_sampling();
  out.mutable_objective()->mutable_robust()->set_members(members);
  out.mutable_objective()->mutable_robust()->set_seed(seed);
  *out.mutable_bounds() = study.bounds();
  *out.mutable_constraints() = study.constraints();
  out.mutable_sweep()->set_top_k(0);
  *out.mutable_sweep()->add_factors() = GaitFactor(study, request);
  *out.mutable_validate() = request;
  out.mutable_validate()->set_members(members);
  out.mutable_validate()->set_seed(seed);
  return out;
}

absl::StatusOr<std::vector<std::vector<double>>> ParseGaits(const std::string& text,
                                                            const std::string& path, int genes) {
  std::vector<std::vector<double>> out;
  int line_no = 0;
  for (absl::string_view line : absl::StrSplit(text, '\n')) {
    ++line_no;
    line = line.substr(0, line.find('#'));
    std::vector<double> gait;
    for (absl::string_view item : absl::StrSplit(line, absl::ByAnyChar(" ,\t\r"), absl::SkipEmpty())) {
      double x = 0;
      if (!absl::SimpleAtod(item, &x) || !std::isfinite(x))
        return absl::InvalidArgumentError(
            absl::StrCat(path, ":", line_no, ": '", item, "' is not a finite number"));
      gait.push_back(x);
    }
    if (gait.empty()) continue;
    if (static_cast<int>(gait.size()) != genes)
      return absl::InvalidArgumentError(absl::StrCat(path, ":", line_no, ": ", gait.size(),
                                                     " genes; the study's space has ", genes));
    out.push_back(std::move(gait));
  }
  if (out.empty()) return absl::InvalidArgumentError(absl::StrCat(path, ": no gaits (one per line)"));
  return out;
}

}  // namespace gaitforge::spec
