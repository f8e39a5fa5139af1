// A diagnosis report (diagnosis.json, report.cc) in words, as `gaitforge diagnose` and
// `gaitforge diagnosis ID` print it: the verdict, each named effect's magnitudes with their
// ranges, the errors before and after, where the mismatch showed, the figures, and the
// runners-up with why they lost. Reads only the report, so a stored diagnosis prints the
// same on any machine.
#pragma once

#include <string>

#include "absl/status/statusor.h"

namespace gaitforge::diagnosis {

absl::StatusOr<std::string> ReportWords(const std::string& report_json);

}  // namespace gaitforge::diagnosis
