// Another resolution of a robot (count_override.h).
#include "robots/count_override.h"

#include <vector>

#include <yaml-cpp/yaml.h>

#include "absl/status/status.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "robots/descriptor_parser.h"

namespace gaitforge::robots {

absl::StatusOr<std::string> WithCount(std::string_view text, std::string_view name, int value,
                                      const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(std::string(text));
  } catch (const YAML::Exception& e) {
    return absl::InvalidArgumentError(absl::StrCat(source, ": ", e.what()));
  }
  const YAML::Node counts = root.IsMap() ? root["counts"] : YAML::Node();
  std::vector<std::string> known;
  if (counts && counts.IsMap())
    for (const auto& kv : counts) known.push_back(kv.first.Scalar());
  const YAML::Node count = counts && counts.IsMap() ? counts[std::string(name)] : YAML::Node();
  const YAML::Node number = count && count.IsMap() ? count["value"] : YAML::Node();
  if (!number || !number.IsScalar())
    return absl::NotFoundError(absl::StrCat(
        source, ": no count '", std::string(name), "' (its counts: ",
        known.empty() ? "none" : absl::StrJoin(known, ", "), ")"));
  const size_t pos = static_cast<size_t>(number.Mark().pos);
  const std::string& old = number.Scalar();
  if (text.substr(pos, old.size()) != old)  // a quoted or tagged scalar: not a plain number
    return absl::InvalidArgumentError(absl::StrCat(
        source, ":", number.Mark().line + 1, ": counts.", std::string(name),
        ".value must be a plain number to be set"));
  std::string out(text);
  out.replace(pos, old.size(), std::to_string(value));
  if (auto parsed = ParseDescriptor(out, source); !parsed.ok()) return parsed.status();
  return out;
}

}  // namespace gaitforge::robots
