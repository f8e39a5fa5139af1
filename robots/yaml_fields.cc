#include "robots/yaml_fields.h"

#include <cmath>
#include <map>

#include "absl/strings/numbers.h"
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

absl::StatusOr<std::string> YamlFields::Scalar(const YAML::Node& node,
                                               const std::string& path) const {
  auto text = Substitute(node.Scalar(), vars_);
  if (!text.ok()) return Error(node, path, std::string(text.status().message()));
  return text;
}

absl::StatusOr<std::string> YamlFields::String(const YAML::Node& node,
                                               const std::string& path) const {
  if (!node.IsDefined() || node.IsNull()) return Error(node, path, "missing (a text)");
  if (!node.IsScalar()) return Error(node, path, "must be a text");
  return Scalar(node, path);
}

absl::Status YamlFields::ForEachItem(
    const YAML::Node& node, const std::string& path,
    const std::function<absl::Status(const YAML::Node&, const std::string&)>& fn) const {
  for (size_t i = 0; i < node.size(); ++i) {
    const YAML::Node item = node[i];
    const std::string at = absl::StrCat(path, "[", i, "]");
    if (!item.IsMap() || !item["repeat"]) {
      if (absl::Status s = fn(item, at); !s.ok()) return s;
      continue;
    }
    if (absl::Status s = CheckMap(item, at, {"repeat", "item"}); !s.ok()) return s;
    const YAML::Node rep = item["repeat"];
    if (!rep.IsMap() || rep.size() != 1 || !rep.begin()->second.IsSequence() ||
        rep.begin()->second.size() != 2)
      return Error(rep, at + ".repeat", "must be {NAME: [FROM, TO]}, e.g. {k: [1, $lumps]}");
    const std::string name = rep.begin()->first.Scalar();
    if (vars_.count(name))
      return Error(rep, at + ".repeat", absl::StrCat("$", name, " is already a variable here"));
    double bounds[2];
    for (int b = 0; b < 2; ++b) {
      const YAML::Node n = rep.begin()->second[b];
      auto text = Scalar(n, absl::StrCat(at, ".repeat.", name, "[", b, "]"));
      if (!text.ok()) return text.status();
      if (!absl::SimpleAtod(*text, &bounds[b]) || bounds[b] != std::round(bounds[b]))
        return Error(n, absl::StrCat(at, ".repeat.", name, "[", b, "]"),
                     absl::StrCat("must be a whole number, got '", *text, "'"));
    }
    if (!item["item"]) return Error(item, at + ".item", "missing (the item to repeat)");
    for (double v = bounds[0]; v <= bounds[1]; ++v) {
      SetVariable(name, v);
      absl::Status s = fn(item["item"], absl::StrCat(at, " (", name, " = ", v, ")"));
      UnsetVariable(name);
      if (!s.ok()) return s;
    }
  }
  return absl::OkStatus();
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
  absl::Status st = ForEachItem(node, path, [&](const YAML::Node& item, const std::string& at) {
    auto s = String(item, at);
    if (s.ok()) out.push_back(*s);
    return s.status();
  });
  if (!st.ok()) return st;
  if (out.empty()) return Error(node, path, "must be a non-empty list of names");
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
