#include "services/dashboard/json_text.h"

#include <cmath>

#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "services/core/json_text.h"

namespace gaitforge::dashboard {

std::string JsonString(const std::string& s) { return core::JsonQuote(s); }

std::string JsonNumber(double x) {
  if (std::isnan(x)) return "\"NaN\"";
  if (std::isinf(x)) return x > 0 ? "\"Infinity\"" : "\"-Infinity\"";
  return absl::StrFormat("%.17g", x);
}

std::string JsonObject(const std::vector<std::pair<std::string, std::string>>& fields) {
  std::vector<std::string> parts;
  for (const auto& [k, v] : fields) parts.push_back(JsonString(k) + ":" + v);
  return "{" + absl::StrJoin(parts, ",") + "}";
}

std::string JsonArray(const std::vector<std::string>& values) {
  return "[" + absl::StrJoin(values, ",") + "]";
}

}  // namespace gaitforge::dashboard
