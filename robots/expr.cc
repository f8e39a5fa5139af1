#include "robots/expr.h"

#include <cctype>
#include <cmath>
#include <cstdlib>

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"

namespace gaitforge::robots {
namespace {

bool NameChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.'; }

// A number at text[at]: advances `at`; false when there is none.
bool ReadNumber(const std::string& text, size_t& at, double& v) {
  const char* begin = text.c_str() + at;
  if (!(std::isdigit(static_cast<unsigned char>(*begin)) || *begin == '.')) return false;
  char* end = nullptr;
  v = std::strtod(begin, &end);
  if (end == begin || !std::isfinite(v)) return false;
  at += static_cast<size_t>(end - begin);
  return true;
}

bool ReadName(const std::string& text, size_t& at, std::string& name) {
  const size_t start = at;
  while (at < text.size() && NameChar(text[at])) ++at;
  name = text.substr(start, at - start);
  return !name.empty() && !std::isdigit(static_cast<unsigned char>(name[0]));
}

void SkipSpace(const std::string& text, size_t& at) {
  while (at < text.size() && text[at] == ' ') ++at;
}

}  // namespace

double Expr::Eval(const std::function<double(const std::string&)>& value_of) const {
  double v = constant;
  for (const auto& t : terms) v += t.coef * value_of(t.name);
  return v;
}

absl::StatusOr<Expr> ParseExpr(const std::string& input) {
  Expr e;
  e.text = input;
  const std::string text(absl::StripAsciiWhitespace(input));
  auto bad = [&]() {
    return absl::InvalidArgumentError(absl::StrCat(
        "'", input, "' is not a number, a parameter name or a sum of terms such as "
        "0.5*body.height_m + 0.002"));
  };
  size_t at = 0;
  bool first = true;
  while (true) {
    SkipSpace(text, at);
    double sign = 1;
    if (at < text.size() && (text[at] == '+' || text[at] == '-')) {
      sign = text[at] == '-' ? -1 : 1;
      ++at;
      SkipSpace(text, at);
    } else if (!first) {
      return bad();
    }
    double number = 1;
    std::string name;
    const bool has_number = ReadNumber(text, at, number);
    SkipSpace(text, at);
    if (has_number && at < text.size() && text[at] == '*') {
      ++at;
      SkipSpace(text, at);
      if (!ReadName(text, at, name)) return bad();
    } else if (!has_number) {
      if (!ReadName(text, at, name)) return bad();
      SkipSpace(text, at);
      if (at < text.size() && text[at] == '*') {
        ++at;
        SkipSpace(text, at);
        if (!ReadNumber(text, at, number)) return bad();
      }
    }
    if (name.empty()) {
      e.constant += sign * number;
    } else {
      e.terms.push_back({sign * number, name});
    }
    first = false;
    SkipSpace(text, at);
    if (at >= text.size()) break;
  }
  if (first) return bad();
  return e;
}

}  // namespace gaitforge::robots
