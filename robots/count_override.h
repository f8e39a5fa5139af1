#pragma once
// Another resolution of a robot made of N alike parts (docs/robots.md, "Counts and
// repeats"): its descriptor's text with one count set to another value. Only that number
// changes, so every message about the result still names the lines of the original file.
// Used where a tool needs the same robot at another N: the gap finder's resolution stage
// (docs/diagnosis.md, "Structure first"), references for test cases, benchmarks.
#include <string>
#include <string_view>

#include "absl/status/statusor.h"

namespace gaitforge::robots {

// `text` with counts.NAME.value set to `value`, checked by the descriptor's own parser
// (`source` names the text in its errors). Errors: the text declares no count NAME (the
// ones it declares are listed), the value is outside the count's range (the parser's own
// message, with the line).
absl::StatusOr<std::string> WithCount(std::string_view text, std::string_view name, int value,
                                      const std::string& source);

}  // namespace gaitforge::robots
