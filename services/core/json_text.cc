#include "services/core/json_text.h"

#include <cmath>
#include <cstdio>

#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"

namespace gaitforge::core {

std::string JsonQuote(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (ch == '\n') {
      out += "\\n";
    } else if (static_cast<unsigned char>(ch) < 0x20) {
      out += absl::StrFormat("\\u%04x", static_cast<unsigned char>(ch));
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

std::string JsonNum(double x) { return std::isfinite(x) ? absl::StrFormat("%.6g", x) : "null"; }

std::string JsonNumList(const std::vector<double>& v) {
  std::vector<std::string> parts;
  for (double x : v) parts.push_back(JsonNum(x));
  return "[" + absl::StrJoin(parts, ", ") + "]";
}

std::string JsonStringList(const std::vector<std::string>& v) {
  std::vector<std::string> parts;
  for (const auto& s : v) parts.push_back(JsonQuote(s));
  return "[" + absl::StrJoin(parts, ", ") + "]";
}

}  // namespace gaitforge::core
