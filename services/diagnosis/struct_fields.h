#pragma once
// Reading a report parsed as a protobuf Struct (the gap finder's JSON): a field, or null
// when absent. Shared by the report in words (words.cc) and the plan (plan.cc).
#include <string>

#include "google/protobuf/struct.pb.h"

namespace gaitforge::diagnosis {

inline const google::protobuf::Value& Field(const google::protobuf::Struct& s,
                                            const std::string& k) {
  static const google::protobuf::Value null;
  const auto it = s.fields().find(k);
  return it == s.fields().end() ? null : it->second;
}

}  // namespace gaitforge::diagnosis
