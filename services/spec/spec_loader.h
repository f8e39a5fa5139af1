#pragma once
// Study specs as files: YAML or JSON that map one to one onto gaitforge.v1.StudySpec.
// Field names are the proto's snake_case names; unknown fields are errors. Every error
// names the file, line and column, the field path and what was expected.
#include <map>
#include <string>

#include "absl/status/statusor.h"
#include "gaitforge/v1/study.pb.h"

namespace gaitforge::spec {

struct Mark {
  int line = 0;    // 1-based
  int column = 0;  // 1-based
};

struct LoadedSpec {
  gaitforge::v1::StudySpec spec;
  std::string source;                  // file name, for messages
  std::map<std::string, Mark> marks;   // field path ("bounds[2].lo") -> where it was written
  // Integers written beyond their type (path -> the text as written). The field holds the
  // type's nearest bound, which validation refuses with the field's own allowed range.
  std::map<std::string, std::string> clamped;
};

// Parses YAML (JSON is accepted as the YAML subset it is). `source` names the text in errors.
absl::StatusOr<LoadedSpec> ParseSpec(const std::string& text, const std::string& source);
absl::StatusOr<LoadedSpec> LoadSpecFile(const std::string& path);

// Parses YAML/JSON text into any message, with the same rules (used for other file kinds):
// unknown fields and keys written twice are errors. With `clamped`, an integer beyond its
// type is stored as the type's nearest bound and listed there; without, it is an error.
absl::Status ParseMessage(const std::string& text, const std::string& source,
                          google::protobuf::Message* message, std::map<std::string, Mark>* marks,
                          std::map<std::string, std::string>* clamped = nullptr);

}  // namespace gaitforge::spec
