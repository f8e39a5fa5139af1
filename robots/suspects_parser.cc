#include "robots/suspects_parser.h"

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"

namespace gaitforge::robots {
namespace {

using Status = absl::Status;

// One `fit` entry NAME: [lo, hi]: a calibratable parameter (its range inside the
// parameter's) or a scale (a positive factor range); both must hold the model as it is.
Status ParseFit(const YamlFields& f, const YAML::Node& key, const YAML::Node& value,
                const std::string& path, const RobotDescriptor& d, Suspect::Fit& out) {
  out.name = key.Scalar();
  if (Status s = f.Range(value, path, out.lo, out.hi); !s.ok()) return s;
  if (!(out.lo < out.hi)) return f.Error(value, path, "needs lo < hi");
  if (const Parameter* p = d.FindParameter(out.name); p && p->calibratable) {
    if (out.lo < p->lo || out.hi > p->hi)
      return f.Error(value, path, absl::StrCat("must lie inside ", out.name, "'s range ", p->RangeText()));
    out.nominal = p->value;
    out.unit = p->unit;
  } else if (d.FindScale(out.name)) {
    if (!(out.lo > 0)) return f.Error(value, path, "a scale's range must be positive factors");
    out.nominal = 1;
  } else {
    const std::vector<std::string> known = d.CalibratableNames();
    return f.Error(key, path,
                   absl::StrCat("'", out.name,
                                "' is not a calibratable parameter (calibrate: true) or a scale "
                                "of this robot; nearest: ",
                                absl::StrJoin(Nearest(out.name, known), ", ")));
  }
  if (!(out.nominal >= out.lo && out.nominal <= out.hi))
    return f.Error(value, path,
                   absl::StrCat("must hold the model's own value ", out.nominal,
                                " (the suspect absent)"));
  return absl::OkStatus();
}

Status ParseSuspect(const YamlFields& f, const YAML::Node& node, const std::string& path,
                    RobotDescriptor& d, Suspect& s) {
  if (Status st = f.CheckMap(node, path, {"name", "meaning", "where", "experiment", "fit"}); !st.ok())
    return st;
  for (auto [key, out] : {std::pair{"name", &s.name}, std::pair{"meaning", &s.meaning},
                          std::pair{"where", &s.where}, std::pair{"experiment", &s.experiment}}) {
    auto t = f.String(node[key], JoinPath(path, key));
    if (!t.ok()) return t.status();
    *out = *t;
  }
  const std::string what = "a mapping NAME: [lo, hi] of the parameters or scales to fit";
  if (!node["fit"]) return f.Error(node, JoinPath(path, "fit"), "missing: " + what);
  const YAML::Node fit = node["fit"];
  if (!fit.IsMap() || fit.size() == 0) return f.Error(fit, JoinPath(path, "fit"), what);
  if (Status st = f.CheckNoDuplicates(fit, JoinPath(path, "fit")); !st.ok()) return st;
  for (const auto& kv : fit) {
    Suspect::Fit one;
    if (Status st = ParseFit(f, kv.first, kv.second, JoinPath(JoinPath(path, "fit"), kv.first.Scalar()),
                             d, one);
        !st.ok())
      return st;
    s.fit.push_back(std::move(one));
  }
  return absl::OkStatus();
}

}  // namespace

Status ParseSuspects(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d) {
  if (!node.IsMap()) return f.Error(node, "suspects", "expected a mapping ID: {name, meaning, ...}");
  if (Status s = f.CheckNoDuplicates(node, "suspects"); !s.ok()) return s;
  for (const auto& kv : node) {
    Suspect s;
    s.id = kv.first.Scalar();
    s.mark = f.MarkOf(kv.first);
    const std::string path = JoinPath("suspects", s.id);
    if (s.id.find('+') != std::string::npos || s.id.empty())
      return f.Error(kv.first, path, "an id may not be empty or hold '+' (it joins pairs)");
    if (Status st = ParseSuspect(f, kv.second, path, d, s); !st.ok()) return st;
    d.suspects.push_back(std::move(s));
  }
  return absl::OkStatus();
}

Status ParseRuledOut(const YamlFields& f, const YAML::Node& node, RobotDescriptor& d) {
  const std::string what = "expected a mapping EFFECT_ID: WHY (the reason the build rules it out)";
  if (!node.IsMap()) return f.Error(node, "ruled_out", what);
  if (Status s = f.CheckNoDuplicates(node, "ruled_out"); !s.ok()) return s;
  for (const auto& kv : node) {
    RuledOut r{kv.first.Scalar(), "", f.MarkOf(kv.first)};
    const std::string path = JoinPath("ruled_out", r.id);
    auto why = f.String(kv.second, path);
    if (!why.ok()) return why.status();
    if (why->empty()) return f.Error(kv.second, path, "needs the reason (" + what + ")");
    r.why = *why;
    d.ruled_out.push_back(std::move(r));
  }
  return absl::OkStatus();
}

}  // namespace gaitforge::robots
