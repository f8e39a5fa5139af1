#include "workers/objectives/overrides.h"

#include <cmath>
#include <cstdlib>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"

namespace gaitforge::objectives {

absl::StatusOr<std::vector<std::pair<std::string, double>>> ParseOverrides(
    const std::string& text) {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& part : absl::StrSplit(text, ',', absl::SkipEmpty())) {
    const std::string s(part);
    const size_t eq = s.find('=');
    char* end = nullptr;
    const double v = eq == std::string::npos ? 0 : std::strtod(s.c_str() + eq + 1, &end);
    if (eq == std::string::npos || eq == 0 || !end || *end || !std::isfinite(v))
      return absl::InvalidArgumentError(absl::StrCat("'", s, "': expected NAME=NUMBER"));
    out.emplace_back(s.substr(0, eq), v);
  }
  return out;
}

}  // namespace gaitforge::objectives
