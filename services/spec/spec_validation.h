#pragma once
// Defaults and validation of StudySpec: one validator for files and for the wire.
#include <map>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "gaitforge/v1/study.pb.h"
#include "services/spec/spec_loader.h"

namespace gaitforge::spec {

struct FieldError {
  std::string path;     // "population", "bounds[2].lo", "objective.params.work_us"
  std::string message;  // what is wrong and the allowed range
};

// Fills what the user may leave out: engine "ga", name "study", the objective's default
// search space, ga.elite 10 and ga.mutation_rate 0.10 (paper 000's values).
void ApplyDefaults(gaitforge::v1::StudySpec* spec);

// Every problem, in field order. Empty means valid. Call after ApplyDefaults.
std::vector<FieldError> Validate(const gaitforge::v1::StudySpec& spec);

// INVALID_ARGUMENT listing every error as "field 'path' message" (OK if none). With
// marks, each error is prefixed with "source:line:column: " where the field was written,
// and integers the loader clamped are shown as written.
absl::Status ValidationStatus(const std::vector<FieldError>& errors,
                              const LoadedSpec* where = nullptr);

}  // namespace gaitforge::spec
