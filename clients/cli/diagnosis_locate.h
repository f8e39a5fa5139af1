// Locating the mismatch (docs/diagnosis.md step 3): the baseline's residuals sliced by
// clients/python/gaitforge_locate.py, against the model's own spread under the numeric
// variants.
#pragma once

#include <string>
#include <vector>

#include "clients/cli/diagnosis_fits.h"
#include "gaitforge/v1/diagnosis.pb.h"

namespace gaitforge::cli::diagnosis {

// c's fit on files (written under dir/stem and dir/stem-variant-K) sliced by the locate
// script into dir/out_json (and figure, when not empty). Returns the located JSON, or "{}"
// with a warning on stderr: locating describes, it does not decide.
std::string Locate(const Candidate& c, const std::vector<std::string>& files,
                   const v1::DiagnosisSpec& d, const std::string& dir, const std::string& stem,
                   const std::string& out_json, const std::string& figure);

}  // namespace gaitforge::cli::diagnosis
