#pragma once
// Defaults and validation of objective.robust (docs/objectives.md, "Robust evaluation").
#include <vector>

#include "gaitforge/v1/study.pb.h"
#include "services/core/objective_catalog.h"
#include "services/spec/spec_validation.h"

namespace gaitforge::spec {

// The largest ensemble objective.robust.members allows.
constexpr int kMaxEnsembleMembers = 256;

// Fills what objective.robust may leave out: seed (the study's), statistic mean, quantile
// 0.25, k 1, start_phases 1, "standard" numerics (the robot's, robots/numerics.h) and
// members (one per numeric variant and start phase). No-op without objective.robust.
void ApplyRobustDefaults(gaitforge::v1::StudySpec* spec);

// Appends objective.robust's errors (none without it).
void ValidateRobust(const gaitforge::v1::StudySpec& spec, const core::ObjectiveInfo& info,
                    std::vector<FieldError>& errors);

}  // namespace gaitforge::spec
