#pragma once
// The spec of a validation study (docs/objectives.md, "Validation"): gaits a robust study
// chose, evaluated once each over a fresh ensemble, one its selection never saw. A robust
// study ranks every genotype on the same few members (common random numbers), so the
// gaits it keeps are those that happen to do well on those members: their ensemble mean
// is optimistic, the more so the fewer the members and the more genotypes it compared.
// The fresh ensemble's mean is a prediction without that selection.
#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "gaitforge/v1/study.pb.h"

namespace gaitforge::spec {

// OK when study `id` has an ensemble to draw afresh (objective.robust).
absl::Status Validatable(const v1::StudySpec& study, const std::string& id);

// A one-generation factorial sweep whose single factor `gait` has one level per gait of
// `request` (every gene set), with the study's objective (its stored, resolved model) and
// the ensemble's members and seed replaced; `validate` holds the request resolved.
// Refused: a study without objective.robust, no gaits, a gait of the wrong length or
// outside the bounds, members outside 1..256, a seed equal to the study's.
absl::StatusOr<v1::StudySpec> ValidationSpec(const v1::StudySpec& study,
                                             const v1::Validation& request);

// Gaits from a text file: one per line, genes separated by spaces or commas ('#' starts a
// comment); errors name the file and line.
absl::StatusOr<std::vector<std::vector<double>>> ParseGaits(const std::string& text,
                                                            const std::string& path,
                                                            int genes);

}  // namespace gaitforge::spec
