// A diagnosis report (diagnosis.json, report.cc) in words, as `gaitforge diagnose` and
// `gaitforge diagnosis ID` print it: the verdict, each named effect's magnitudes with their
// ranges, the errors before and after, where the mismatch showed, the figures, and the
// runners-up with why they lost. Reads only the report, so a stored diagnosis prints the
// same on any machine.
#pragma once

#include <string>

#include "absl/status/statusor.h"

namespace gaitforge::diagnosis {

// With `dir`, the report's files are named in dir (where a client copied them) instead of
// the folder the report was written in.
absl::StatusOr<std::string> ReportWords(const std::string& report_json,
                                        const std::string& dir = "");

}  // namespace gaitforge::diagnosis
