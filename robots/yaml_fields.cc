#include "robots/yaml_fields.h"

#include <cmath>
#include <map>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace gaitforge::robots {

std::string JoinPath(const std::string& prefix, const std::string& key) {
  return prefix.empty() ? key : absl::StrCat(prefix, ".", key);
}

absl::StatusOr<YAML::Node> LoadYaml(const std::string& text, const std::string& source) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat(source, ":", e.mark.line + 1, ":",
                                                   e.mark.column + 1, ": not YAML/JSON: ", e.msg));
  }
}

Mark YamlFields::MarkOf(const YAML::Node& node) const {
  Mark m{source_, 0, 0};
  if (!node.IsDefined()) return m;
  const YAML::Mark y = node.Mark();
  if (y.line >= 0) {
    m.line = y.line + 1;
    m.column = y.column + 1;
  }
  return m;
}

absl::Status YamlFields::Error(const YAML::Node& node, const std::string& path,
                               const std::string& what) const {
  return absl::InvalidArgumentError(
      absl::StrCat(MarkOf(node).ToString(), ": ", path.empty() ? "" : path + ": ", what));
}

absl::Status YamlFields::CheckNoDuplicates(const YAML::Node& node, const std::string& path) const {
  if (!node.IsMap()) return Error(node, path, "expected a mapping");
  std::map<std::string, YAML::Node> seen;
  for (const auto& kv : node) {
    const std::string key = kv.first.Scalar();
    auto [it, fresh] = seen.emplace(key, kv.first);
    if (!fresh) {
      return Error(kv.first, JoinPath(path, key),
                   absl::StrCat("written twice, here and at line ", MarkOf(it->second).line,
                                " (a key may appear once)"));
    }
  }
  return absl::OkStatus();
}

absl::Status YamlFields::CheckMap(const YAML::Node& node, const std::string& path,
                                  const std::vector<std::string>& allowed) const {
  if (absl::Status s = CheckNoDuplicates(node, path); !s.ok()) return s;
  for (const auto& kv : node) {
    const std::string key = kv.first.Scalar();
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    return Error(kv.first, JoinPath(path, key),
                 absl::StrCat("unknown field; did you mean ",
                              absl::StrJoin(Nearest(key, allowed), ", "),
                              "? (known: ", absl::StrJoin(allowed, ", "), ")"));
  }
  return absl::OkStatus();
}

absl::StatusOr<std::string> YamlFields::String(const YAML::Node& node,
                                               const std::string& path) const {
  if (!node.IsDefined() || node.IsNull()) return Error(node, path, "missing (a text)");
  if (!node.IsScalar()) return Error(node, path, "must be a text");
  return node.Scalar();
}

absl::StatusOr<double> YamlFields::Number(const YAML::Node& node, const std::string& path,
                                          bool allow_infinite) const {
  const char* want = allow_infinite ? "a number or infinite" : "a finite number";
  if (!node.IsDefined() || node.IsNull()) return Error(node, path, absl::StrCat("missing (", want, ")"));
  double v = 0;
  if (allow_infinite && node.IsScalar() && node.Scalar() == "infinite") return INFINITY;
  if (!node.IsScalar() || !YAML::convert<double>::decode(node, v) || std::isnan(v) ||
      (std::isinf(v) && !(allow_infinite && v > 0))) {
    return Error(node, path,
                 absl::StrCat("must be ", want, ", got '", node.IsScalar() ? node.Scalar() : "?",
                              "'"));
  }
  return v;
}

absl::StatusOr<bool> YamlFields::Bool(const YAML::Node& node, const std::string& path) const {
  bool b = false;
  if (!node.IsScalar() || !YAML::convert<bool>::decode(node, b))
    return Error(node, path, "must be true or false");
  return b;
}

absl::StatusOr<std::vector<std::string>> YamlFields::StringList(const YAML::Node& node,
                                                                const std::string& path) const {
  if (!node.IsDefined() || !node.IsSequence() || node.size() == 0)
    return Error(node, path, "must be a non-empty list of names");
  std::vector<std::string> out;
  for (size_t i = 0; i < node.size(); ++i) {
    auto s = String(node[i], absl::StrCat(path, "[", i, "]"));
    if (!s.ok()) return s.status();
    out.push_back(*s);
  }
  return out;
}

absl::Status YamlFields::Range(const YAML::Node& node, const std::string& path, double& lo,
                               double& hi) const {
  if (!node.IsDefined() || !node.IsSequence() || node.size() != 2)
    return Error(node, path, "must be [lo, hi]");
  auto l = Number(node[0], path + "[0]");
  if (!l.ok()) return l.status();
  auto h = Number(node[1], path + "[1]");
  if (!h.ok()) return h.status();
  if (*l > *h) return Error(node, path, "lo must not exceed hi");
  lo = *l;
  hi = *h;
  return absl::OkStatus();
}

}  // namespace gaitforge::robots
