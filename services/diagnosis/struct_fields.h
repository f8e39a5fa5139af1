#pragma once
// Reading a report parsed as a protobuf Struct (the gap finder's JSON): a field, or null
// when absent; a number. Shared by the report in words (words.cc) and the plan (plan.cc).
#include <string>

#include "google/protobuf/struct.pb.h"

namespace gaitforge::diagnosis {

inline const google::protobuf::Value& Field(const google::protobuf::Struct& s,
                                            const std::string& k) {
  static const google::protobuf::Value null;
  const auto it = s.fields().find(k);
  return it == s.fields().end() ? null : it->second;
}

// A number field, or `fallback` when it is absent or not a number.
inline double Number(const google::protobuf::Struct& s, const std::string& k, double fallback) {
  const google::protobuf::Value& v = Field(s, k);
  return v.kind_case() == google::protobuf::Value::kNumberValue ? v.number_value() : fallback;
}

}  // namespace gaitforge::diagnosis
