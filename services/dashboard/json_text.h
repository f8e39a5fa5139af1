#pragma once
// JSON text of the few answers that are no protobuf message (errors, a study's robot),
// written in a fixed key order so that equal answers are equal bytes (their ETags match).
#include <string>
#include <vector>

namespace gaitforge::dashboard {

// `s` as a JSON string literal (core::JsonQuote: the one quoting rule of gaitforge's JSON).
std::string JsonString(const std::string& s);
// `x` as a JSON number, or a string "NaN", "Infinity", "-Infinity" as proto3 JSON does.
std::string JsonNumber(double x);
// {"k1": v1, ...} from keys and already-encoded values, in the order given.
std::string JsonObject(const std::vector<std::pair<std::string, std::string>>& fields);
// [v1, ...] from already-encoded values.
std::string JsonArray(const std::vector<std::string>& values);

}  // namespace gaitforge::dashboard
