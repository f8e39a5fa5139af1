// The diagnosis spec (proto/gaitforge/v1/diagnosis.proto, docs/diagnosis.md): defaults and
// validation, each error naming the field and what it allows.
#pragma once

#include "absl/status/status.h"
#include "gaitforge/v1/diagnosis.pb.h"

namespace gaitforge::diagnosis {

absl::Status Validate(const v1::DiagnosisSpec& d);
void Defaults(v1::DiagnosisSpec* d);

}  // namespace gaitforge::diagnosis
