#include "services/dashboard/json_text.h"

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>

#include <cmath>

#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"

namespace gaitforge::dashboard {

std::string JsonString(const std::string& s) {
  google::protobuf::Value v;
  v.set_string_value(s);
  std::string out;
  (void)google::protobuf::util::MessageToJsonString(v, &out);
  return out;
}

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
