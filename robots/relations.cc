#include "robots/relations.h"

#include "absl/strings/ascii.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace gaitforge::robots {
namespace {

// "a + b - c" into signed terms; false on an empty term.
bool ParseSide(std::string_view text, std::vector<Relation::Term>& out) {
  double sign = 1;
  std::string name;
  auto flush = [&]() {
    const std::string n(absl::StripAsciiWhitespace(name));
    if (n.empty()) return false;
    out.push_back({sign, n});
    name.clear();
    return true;
  };
  for (char c : text) {
    if (c == '+' || c == '-') {
      if (!(name.empty() && out.empty() && c == '-') && !flush()) return false;
      sign = c == '-' ? -1 : 1;
    } else {
      name += c;
    }
  }
  return flush();
}

absl::Status ParseOne(const YamlFields& f, const YAML::Node& node, const std::string& path,
                      RobotDescriptor& d) {
  Relation r;
  YAML::Node text_node;
  text_node.reset(node);  // operator= would assign into the tree
  if (node.IsMap()) {
    if (absl::Status s = f.CheckMap(node, path, {"check", "why"}); !s.ok()) return s;
    text_node.reset(node["check"]);
    if (node["why"]) {
      auto why = f.String(node["why"], path + ".why");
      if (!why.ok()) return why.status();
      r.why = *why;
    }
  }
  auto text = f.String(text_node, path);
  if (!text.ok()) return text.status();
  r.text = *text;
  r.mark = f.MarkOf(text_node);
  size_t at = std::string::npos;
  for (const char* op : {"<=", ">=", "<", ">"}) {
    at = r.text.find(op);
    if (at != std::string::npos) {
      r.op = op;
      break;
    }
  }
  if (at == std::string::npos || !ParseSide(r.text.substr(0, at), r.lhs) ||
      !ParseSide(r.text.substr(at + r.op.size()), r.rhs)) {
    return f.Error(text_node, path,
                   "must read 'A + B - C <= D' (parameter names joined by + and -, one of "
                   "< <= > >=)");
  }
  std::vector<std::string> known;
  for (const auto& p : d.parameters) known.push_back(p.name);
  for (const auto* side : {&r.lhs, &r.rhs}) {
    for (const auto& t : *side) {
      if (d.FindParameter(t.name) != nullptr) continue;
      return f.Error(text_node, path,
                     absl::StrCat("'", t.name, "' is not a parameter of this robot; nearest: ",
                                  absl::StrJoin(Nearest(t.name, known), ", ")));
    }
  }
  d.relations.push_back(std::move(r));
  return absl::OkStatus();
}

}  // namespace

absl::Status ParseRelations(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d) {
  if (!node.IsSequence()) return f.Error(node, "relations", "must be a list");
  for (size_t i = 0; i < node.size(); ++i) {
    if (absl::Status s = ParseOne(f, node[i], absl::StrCat("relations[", i, "]"), d); !s.ok())
      return s;
  }
  return absl::OkStatus();
}

}  // namespace gaitforge::robots
