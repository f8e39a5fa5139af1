#pragma once
// A whole file's bytes, for the many places that read a report, a descriptor or a sidecar.
#include <string>

#include "absl/status/statusor.h"

namespace gaitforge::core {

// The file's bytes; NotFound naming `path` when it cannot be opened.
absl::StatusOr<std::string> ReadWholeFile(const std::string& path);

}  // namespace gaitforge::core
