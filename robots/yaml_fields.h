#pragma once
// Strict reading of YAML (or JSON) files into typed values, for robot descriptors and other
// files users write: every error names file:line:column and the field's dotted path, an
// unknown key names the nearest known ones, and a key written twice names both lines
// (yaml-cpp would keep the last one silently).
#include <yaml-cpp/yaml.h>

#include <functional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "robots/descriptor.h"
#include "robots/templates.h"

namespace gaitforge::robots {

class YamlFields {
 public:
  explicit YamlFields(std::string source) : source_(std::move(source)) {}

  const std::string& source() const { return source_; }
  Mark MarkOf(const YAML::Node& node) const;
  // "FILE:LINE:COL: PATH: what" (PATH left out when empty).
  absl::Status Error(const YAML::Node& node, const std::string& path,
                     const std::string& what) const;

  // `node` must be a mapping whose keys are all in `allowed` and none twice.
  absl::Status CheckMap(const YAML::Node& node, const std::string& path,
                        const std::vector<std::string>& allowed) const;
  // A mapping without duplicate keys (any keys).
  absl::Status CheckNoDuplicates(const YAML::Node& node, const std::string& path) const;

  // A scalar's text with the template variables set now substituted (templates.h); the
  // error points at the node. Every text and expression of a descriptor is read through it.
  absl::StatusOr<std::string> Scalar(const YAML::Node& node, const std::string& path) const;
  absl::StatusOr<std::string> String(const YAML::Node& node, const std::string& path) const;
  // A finite number, or +infinity when `allow_infinite` (written .inf or "infinite").
  absl::StatusOr<double> Number(const YAML::Node& node, const std::string& path,
                                bool allow_infinite = false) const;
  absl::StatusOr<bool> Bool(const YAML::Node& node, const std::string& path) const;
  // Items may be repeats (ForEachItem).
  absl::StatusOr<std::vector<std::string>> StringList(const YAML::Node& node,
                                                      const std::string& path) const;

  // Template variables (templates.h): the descriptor's counts, and a repeat's index while
  // its item is read.
  void SetVariable(const std::string& name, double value) const { vars_[name] = value; }
  void UnsetVariable(const std::string& name) const { vars_.erase(name); }
  const TemplateVariables& variables() const { return vars_; }

  // Calls fn(item, path) for each item of the sequence `node`; an item
  // {repeat: {NAME: [FROM, TO]}, item: TEMPLATE} stands for TEMPLATE read once for each whole
  // NAME from FROM to TO (texts, counts allowed: [1, $lumps]) with $NAME set, its path
  // "PATH[i] (NAME = v)".
  absl::Status ForEachItem(
      const YAML::Node& node, const std::string& path,
      const std::function<absl::Status(const YAML::Node&, const std::string&)>& fn) const;
  // [lo, hi] with lo <= hi, both finite.
  absl::Status Range(const YAML::Node& node, const std::string& path, double& lo,
                     double& hi) const;

 private:
  std::string source_;
  mutable TemplateVariables vars_;
};

// "a.b" or "b" when `prefix` is empty.
std::string JoinPath(const std::string& prefix, const std::string& key);

// Parses text as YAML; a syntax error names source:line:column.
absl::StatusOr<YAML::Node> LoadYaml(const std::string& text, const std::string& source);

}  // namespace gaitforge::robots
