#include "services/coordinator/validation.h"

#include "absl/strings/str_cat.h"
#include "services/coordinator/validation_model.h"
#include "services/spec/validation_spec.h"

namespace gaitforge::coordinator {
namespace {

constexpr char kField[] = "validate";

// A spec that already is a validation study (one stored, submitted again): `validate` is
// the record of where it came from, and the spec is checked as any other.
bool Resolved(const v1::StudySpec& spec) {
  return !spec.objective().name().empty() && spec.engine() == "sweep" &&
         spec.validate().gaits_size() > 0;
}

// What a validation spec may not set: it takes them from the study it validates.
absl::Status OnlyTheRequest(const v1::StudySpec& spec) {
  if (spec.validate().top() > 0 && spec.validate().gaits_size() > 0)
    return absl::InvalidArgumentError(absl::StrCat(
        kField, ": top picks hall-of-fame gaits; with gaits given it would be ignored"));
  for (const auto& [set, field] :
       {std::make_pair(spec.has_objective(), "objective"),
        std::make_pair(spec.bounds_size() > 0, "bounds"),
        std::make_pair(spec.constraints_size() > 0, "constraints"),
        std::make_pair(spec.population() != 0, "population"),
        std::make_pair(spec.generations() != 0, "generations")})
    if (set)
      return absl::InvalidArgumentError(absl::StrCat(
          kField, ": a validation study takes its ", field, " from the study it validates; "
          "leave '", field, "' out"));
  return absl::OkStatus();
}

// The first `top` valid gaits (all for 0) of study `id`'s latest hall of fame.
absl::Status HallOfFameGaits(storage::StudyStore& store, const std::string& id,
                             v1::Validation* request) {
  if (auto s = store.Flush(); !s.ok()) return s;
  auto hof = store.HallOfFame(id, std::nullopt);
  if (!hof.ok())
    return absl::Status(hof.status().code(),
                        absl::StrCat(kField, ".study_id: ", hof.status().message()));
  for (const storage::HofRecord& h : hof->second) {
    if (request->top() > 0 && request->gaits_size() == request->top()) break;
    if (h.valid) request->add_gaits()->mutable_genes()->Add(h.genes.begin(), h.genes.end());
  }
  if (request->gaits().empty())
    return absl::FailedPreconditionError(absl::StrCat(
        kField, ".study_id: study ", id, "'s hall of fame holds no valid gait"));
  return absl::OkStatus();
}

}  // namespace

absl::Status ResolveValidation(storage::StudyStore& store, const SpreadFn& spread_after,
                               v1::StudySpec* spec) {
  if (!spec->has_validate() || Resolved(*spec)) return absl::OkStatus();
  if (auto s = OnlyTheRequest(*spec); !s.ok()) return s;
  v1::Validation request = spec->validate();
  const std::string id = request.study_id();
  if (id.empty())
    return absl::InvalidArgumentError(absl::StrCat(
        kField, ".study_id: required (the robust study whose gaits are validated)"));
  auto rec = store.GetStudy(id);
  if (!rec.ok())
    return absl::NotFoundError(absl::StrCat(kField, ".study_id: no study with id '", id, "'"));
  v1::StudySpec study;
  if (!study.ParseFromString(rec->spec))
    return absl::DataLossError(absl::StrCat(kField, ": study ", id, "'s stored spec is unreadable"));
  // Before its hall of fame is read: the reason that matters.
  if (auto s = spec::Validatable(study, id); !s.ok())
    return absl::InvalidArgumentError(absl::StrCat(kField, ": ", s.message()));
  if (request.gaits().empty())
    if (auto s = HallOfFameGaits(store, id, &request); !s.ok()) return s;
  if (!request.from_calibration().empty())
    if (auto s = RebaseOnCalibration(store, spread_after, request.from_calibration(), &study);
        !s.ok())
      return s;
  auto out = spec::ValidationSpec(study, request);
  if (!out.ok()) return absl::InvalidArgumentError(absl::StrCat(kField, ": ", out.status().message()));
  *spec = std::move(*out);
  return absl::OkStatus();
}

}  // namespace gaitforge::coordinator
