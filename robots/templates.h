#pragma once
// Template variables in a descriptor (docs/robots.md, "Counts and repeats"): a robot made of
// N alike parts (paper 004's arm of N lumps) declares N once under `counts:` and writes each
// part once, as a `repeat` item whose index and the counts appear in its texts as `$name`
// or `$(expression)`: "disk$k", "disk$(k-1)", "-$(k/lumps)*arm.length_m". The result is
// ordinary descriptor text, read by the same strict parser.
#include <map>
#include <string>
#include <string_view>

#include "absl/status/statusor.h"

namespace gaitforge::robots {

using TemplateVariables = std::map<std::string, double, std::less<>>;

// `text` with every `$name` and `$(expression)` replaced by its value: expressions of
// numbers, variables, + - * / and parentheses; a whole value prints as an integer ("3"),
// another with 17 significant digits. Text without '$' comes back unchanged. An unknown
// variable, a malformed expression or a division by zero is an error saying which.
absl::StatusOr<std::string> Substitute(std::string_view text, const TemplateVariables& vars);

}  // namespace gaitforge::robots
