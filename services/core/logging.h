#pragma once
// Logging setup shared by every binary: spdlog to stderr, as text or as one JSON object per
// line. In JSON, "key=value" words of a message whose key is one of study, generation,
// member, job, worker or lease also become fields of the object, so that logs can be
// filtered by study, generation, job and worker.
#include <string>

#include "absl/status/status.h"

namespace gaitforge::core {

// level: trace|debug|info|warn|error|off; another is INVALID_ARGUMENT naming the flag
// (`--log-level`) and nothing is set up.
absl::Status SetupLogging(const std::string& program, const std::string& level,
                          bool json = false);

// The JSON line for one message (exposed for tests).
std::string JsonLogLine(const std::string& time, const std::string& level,
                        const std::string& program, const std::string& message);

}  // namespace gaitforge::core
