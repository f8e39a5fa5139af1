// Template variables in a descriptor (templates.h).
#include "robots/templates.h"

#include <cctype>
#include <cmath>

#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"

namespace gaitforge::robots {
namespace {

bool NameStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool NameChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// Recursive descent over sum := product (('+'|'-') product)*, product := unary (('*'|'/')
// unary)*, unary := '-' unary | '(' sum ')' | number | name.
class Evaluator {
 public:
  Evaluator(std::string_view s, const TemplateVariables& vars) : s_(s), vars_(vars) {}

  absl::StatusOr<double> All() {
    auto v = Sum();
    if (v.ok() && (Skip(), pos_ != s_.size())) return Fail("unexpected text");
    return v;
  }

 private:
  void Skip() {
    while (pos_ < s_.size() && s_[pos_] == ' ') ++pos_;
  }
  absl::Status Fail(std::string_view what) const {
    return absl::InvalidArgumentError(
        absl::StrCat(std::string(what), " at '", std::string(s_.substr(pos_)), "' in $(",
                     std::string(s_), ")"));
  }
  absl::StatusOr<double> Sum() {
    auto v = Product();
    while (v.ok() && (Skip(), pos_ < s_.size()) && (s_[pos_] == '+' || s_[pos_] == '-')) {
      const char op = s_[pos_++];
      auto w = Product();
      if (!w.ok()) return w;
      v = op == '+' ? *v + *w : *v - *w;
    }
    return v;
  }
  absl::StatusOr<double> Product() {
    auto v = Unary();
    while (v.ok() && (Skip(), pos_ < s_.size()) && (s_[pos_] == '*' || s_[pos_] == '/')) {
      const char op = s_[pos_++];
      auto w = Unary();
      if (!w.ok()) return w;
      if (op == '/' && *w == 0) return Fail("division by zero");
      v = op == '*' ? *v * *w : *v / *w;
    }
    return v;
  }
  absl::StatusOr<double> Unary() {
    Skip();
    if (pos_ >= s_.size()) return Fail("missing a value");
    if (s_[pos_] == '-') {
      ++pos_;
      auto v = Unary();
      if (v.ok()) return -*v;
      return v;
    }
    if (s_[pos_] == '(') {
      ++pos_;
      auto v = Sum();
      if (v.ok() && (Skip(), pos_ >= s_.size() || s_[pos_++] != ')')) return Fail("missing ')'");
      return v;
    }
    const size_t start = pos_;
    if (NameStart(s_[pos_])) {
      while (pos_ < s_.size() && NameChar(s_[pos_])) ++pos_;
      return Variable(s_.substr(start, pos_ - start));
    }
    while (pos_ < s_.size() && (std::isdigit(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '.'))
      ++pos_;
    double v = 0;
    if (pos_ == start || !absl::SimpleAtod(absl::string_view(s_.data() + start, pos_ - start), &v))
      return (pos_ = start, Fail("expected a number, a name or '('"));
    return v;
  }
  absl::StatusOr<double> Variable(std::string_view name) const {
    auto it = vars_.find(name);
    if (it != vars_.end()) return it->second;
    std::vector<std::string> known;
    for (const auto& [k, v] : vars_) known.push_back(k);
    return absl::InvalidArgumentError(absl::StrCat(
        "unknown template variable $", std::string(name), " (known here: ",
        known.empty() ? "none" : absl::StrJoin(known, ", "), ")"));
  }

  std::string_view s_;
  const TemplateVariables& vars_;
  size_t pos_ = 0;
};

std::string Format(double v) {
  if (std::fabs(v) < 1e15 && v == std::round(v)) return absl::StrCat(static_cast<long long>(v));
  return absl::StrFormat("%.17g", v);
}

}  // namespace

absl::StatusOr<std::string> Substitute(std::string_view text, const TemplateVariables& vars) {
  if (text.find('$') == std::string_view::npos) return std::string(text);
  std::string out;
  for (size_t i = 0; i < text.size();) {
    if (text[i] != '$') {
      out += text[i++];
      continue;
    }
    std::string_view expr;
    size_t end = i + 1;
    if (end < text.size() && text[end] == '(') {
      int depth = 0;
      for (; end < text.size(); ++end) {
        depth += text[end] == '(' ? 1 : text[end] == ')' ? -1 : 0;
        if (depth == 0) break;
      }
      if (end >= text.size())
        return absl::InvalidArgumentError(
            absl::StrCat("'", std::string(text.substr(i)), "': missing ')'"));
      expr = text.substr(i + 2, end - i - 2);
      ++end;
    } else {
      while (end < text.size() && NameChar(text[end])) ++end;
      expr = text.substr(i + 1, end - i - 1);
      if (expr.empty() || !NameStart(expr[0]))
        return absl::InvalidArgumentError(absl::StrCat(
            "'", std::string(text.substr(i)), "': a '$' must start $name or $(expression)"));
    }
    auto v = Evaluator(expr, vars).All();
    if (!v.ok()) return v.status();
    out += Format(*v);
    i = end;
  }
  return out;
}

}  // namespace gaitforge::robots
