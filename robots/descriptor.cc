#include "robots/descriptor.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "absl/strings/str_cat.h"

namespace gaitforge::robots {
namespace {

std::string Num(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

double Sum(const std::vector<Relation::Term>& terms,
           const std::function<double(const std::string&)>& value_of) {
  double s = 0;
  for (const auto& t : terms) s += t.sign * value_of(t.name);
  return s;
}

bool Holds(double l, const std::string& op, double r) {
  // Non-strict relations forgive rounding of sums of decimal numbers.
  const double tol = 1e-9 * std::max({1.0, std::fabs(l), std::fabs(r)});
  if (op == "<") return l < r;
  if (op == ">") return l > r;
  if (op == "<=") return l <= r + tol;
  return l >= r - tol;
}

size_t EditDistance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string Mark::ToString() const {
  if (line <= 0) return source;
  return column > 0 ? absl::StrCat(source, ":", line, ":", column)
                    : absl::StrCat(source, ":", line);
}

std::string Parameter::RangeText() const {
  return absl::StrCat("[", Num(lo), ", ", Num(hi), "]", unit.empty() ? "" : " ", unit,
                      infinite.empty() ? "" : " or infinite");
}

std::string Parameter::Check(double v) const {
  const bool ok = std::isinf(v) ? (v > 0 && !infinite.empty())
                                : (std::isfinite(v) && v >= lo && v <= hi &&
                                   (!integer || v == std::floor(v)));
  if (ok) return "";
  return absl::StrCat(name, " = ", Num(v), unit.empty() ? "" : " ", unit, " is outside ",
                      RangeText(), integer ? " (a whole number)" : "");
}

const Parameter* RobotDescriptor::FindParameter(std::string_view n) const {
  for (const auto& p : parameters)
    if (p.name == n) return &p;
  return nullptr;
}

const Scale* RobotDescriptor::FindScale(std::string_view n) const {
  for (const auto& s : scales)
    if (s.name == n) return &s;
  return nullptr;
}

const Body* RobotDescriptor::FindBody(std::string_view n) const {
  for (const auto& b : bodies)
    if (b.name == n) return &b;
  return nullptr;
}

const Joint* RobotDescriptor::FindJoint(std::string_view n) const {
  for (const auto& j : joints)
    if (j.name == n) return &j;
  return nullptr;
}

double RobotDescriptor::Value(std::string_view n) const {
  const Parameter* p = FindParameter(n);
  if (p == nullptr) throw std::out_of_range(absl::StrCat(name, " has no parameter ", std::string(n)));
  return p->value;
}

std::vector<std::string> RobotDescriptor::CalibratableNames() const {
  std::vector<std::string> names;
  for (const auto& p : parameters)
    if (p.calibratable) names.push_back(p.name);
  for (const auto& s : scales) names.push_back(s.name);
  return names;
}

std::vector<std::string> Joint::AngleFields() const {
  if (type == "universal") return {"angle1", "angle2"};
  if (type == "fixed") return {};
  return {"angle"};
}

std::vector<std::string> RobotDescriptor::Channels() const {
  std::vector<std::string> out;
  for (const auto& s : sensors) {
    for (const auto& n : s.names) {
      if (s.kind == "marker") {
        for (const auto& axis : s.axes) out.push_back(absl::StrCat(n, ".", axis));
      } else if (s.kind == "joint_torque" || s.kind == "joint_rate") {
        out.push_back(absl::StrCat(n, s.kind == "joint_torque" ? ".torque" : ".rate"));
      } else if (const Joint* j = FindJoint(n); j != nullptr) {
        for (const auto& field : j->AngleFields()) out.push_back(absl::StrCat(n, ".", field));
      } else {
        out.push_back(absl::StrCat(n, ".angle"));  // a dedicated model's joint
      }
    }
  }
  return out;
}

std::vector<std::string> RobotDescriptor::InputChannels() const {
  std::vector<std::string> out;
  for (const auto& a : actuators) out.push_back(a.InputChannel());
  return out;
}

std::string Actuator::InputChannel() const {
  if (type == "tendon") return name + ".force";
  if (type == "servo") return name + ".setpoint";
  return name + ".on";
}

std::string Actuator::InputUnit() const {
  if (type == "tendon") return "N";
  if (type == "servo") return "rad";
  return "1";
}

int RobotDescriptor::MarkerCount() const {
  for (const auto& s : sensors)
    if (s.kind == "marker") return static_cast<int>(s.names.size());
  return 0;
}

double RobotDescriptor::MarkerSpacing() const {
  for (const auto& s : sensors)
    if (s.kind == "marker" && !s.spacing.empty()) return Value(s.spacing);
  return 0;
}

absl::Status RobotDescriptor::CheckRelations(
    const std::function<double(const std::string&)>& value_of) const {
  for (const auto& r : relations) {
    const double l = Sum(r.lhs, value_of), rv = Sum(r.rhs, value_of);
    if (Holds(l, r.op, rv)) continue;
    return absl::InvalidArgumentError(
        absl::StrCat(r.mark.ToString(), ": relation '", r.text, "' fails: ", Num(l), " ",
                     r.op, " ", Num(rv), " is false", r.why.empty() ? "" : " (", r.why,
                     r.why.empty() ? "" : ")"));
  }
  return absl::OkStatus();
}

std::vector<std::string> Nearest(std::string_view name, const std::vector<std::string>& known,
                                 size_t count) {
  std::vector<std::pair<size_t, std::string>> scored;
  // A name typed short of its unit suffix ("knee.stifness" for knee.stiffness_nm_per_rad)
  // is near the known name's start: score it there too, one edit worse.
  for (const auto& k : known)
    scored.emplace_back(std::min(EditDistance(name, k),
                                 EditDistance(name, std::string_view(k).substr(0, name.size())) + 1),
                        k);
  std::stable_sort(scored.begin(), scored.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<std::string> out;
  for (size_t i = 0; i < scored.size() && i < count; ++i) out.push_back(scored[i].second);
  return out;
}

}  // namespace gaitforge::robots
