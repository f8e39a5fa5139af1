#pragma once
// "NAME=VALUE,NAME=VALUE": parameter overrides as an objective's option `set`, gaitforge-sim's
// --set and the gap finder's corrected models write them. Applied in order by the model.
#include <string>
#include <utility>
#include <vector>

#include "absl/status/statusor.h"

namespace gaitforge::objectives {

// Each item must be NAME=NUMBER with a finite number; the error quotes the item.
absl::StatusOr<std::vector<std::pair<std::string, double>>> ParseOverrides(
    const std::string& text);

}  // namespace gaitforge::objectives
