#pragma once
// Logging setup shared by every binary: spdlog to stderr.
#include <string>

namespace gaitforge::core {

// level: trace|debug|info|warn|error|off.
void SetupLogging(const std::string& program, const std::string& level);

}  // namespace gaitforge::core
