#pragma once
// Constraints on returned metrics (StudySpec.constraints): the total violation of a result.
#include <map>
#include <string>

#include "gaitforge/v1/study.pb.h"

namespace gaitforge::coordinator {

// Sum over constraints of (distance of the metric outside [min, max]) / scale; 0 when
// feasible or when the result is invalid (invalid already ranks last). A constrained
// metric the result lacks counts as a violation of 1e30, so such a member ranks below
// every member that reported it.
double Violation(const v1::StudySpec& spec, bool valid,
                 const std::map<std::string, double>& metrics);

}  // namespace gaitforge::coordinator
