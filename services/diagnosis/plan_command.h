#pragma once
// gaitforge-sim plan's command line for a diagnosis (plan.h): what `gaitforge diagnose plan`
// runs on a spec and its report, and what a diagnosis runs by itself when its recordings
// could not decide (pipeline.cc; the plan is kept as plan.json beside the report).
#include <string>
#include <vector>

#include "gaitforge/v1/diagnosis.pb.h"
#include "services/diagnosis/plan.h"

namespace gaitforge::diagnosis {

// argv of gaitforge-sim plan: `robot` (a built-in name or a descriptor file), the recordings
// (files), the plan's options (the spec's max_shift_samples wins), the model every
// explanation shares (the report's counts; its step, else the spec's timestep_ms) and the
// spec's channels.
std::vector<std::string> PlanCommand(const v1::DiagnosisSpec& d, const std::string& robot,
                                     const std::vector<std::string>& recordings,
                                     plan::Options o, const plan::ReportModel& m);

}  // namespace gaitforge::diagnosis
