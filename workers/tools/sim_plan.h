#pragma once
// gaitforge-sim plan: the recordings that would separate a diagnosis's leading explanations
// (docs/diagnosis.md, "Plan the experiment that decides"). Every candidate gait
// (services/diagnosis/plan.h) is simulated from rest under every explanation; how far two
// explanations' channels part on it, in multiples of what the model leaves unexplained,
// says whether recording it would tell them apart.
#include <string>

#include "absl/status/statusor.h"
#include "services/diagnosis/plan.h"
#include "workers/tools/generic_sim.h"

namespace gaitforge::simtool {

struct PlanArgs {
  std::string recordings;  // the diagnosis's recordings (CSV paths with sidecars), comma separated
  std::string channels;    // compared channels, comma separated ("": every one the recordings
                           // and the model both have)
  diagnosis::plan::Options options;
};

// The plan as JSON (docs/diagnosis.md): the explanations, every candidate with its
// separation of every pair, the chosen recordings and which pairs stay undecided. run's
// overrides are the model every explanation shares (a diagnosis's timestep, say). An error
// names a bad argument, an unreadable or unusable report, or a recording that is no gait.
absl::StatusOr<std::string> GenericPlan(const GenericRun& run, const PlanArgs& a);

}  // namespace gaitforge::simtool
