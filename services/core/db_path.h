#pragma once
// Where a study database may be: one rule for the coordinator and the CLI.
#include <string>

#include "absl/status/status.h"

namespace gaitforge::core {

// OK if `db` names a file (existing or not) in an existing folder. INVALID_ARGUMENT,
// starting "--db ", for a directory or a missing folder: nothing creates directories for
// a mistyped path.
absl::Status CheckDbPath(const std::string& db);

}  // namespace gaitforge::core
