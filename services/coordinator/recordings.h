#pragma once
// Recordings in the coordinator: validated on upload (services/recording), stored
// content-addressed in the results database, served to clients and workers by hash.
#include <string>

#include "absl/status/statusor.h"
#include "gaitforge/v1/recording.pb.h"
#include "storage/study_store.h"

namespace gaitforge::coordinator {

class Recordings {
 public:
  Recordings(storage::StudyStore& store, size_t max_bytes, bool read_only)
      : store_(store), max_bytes_(max_bytes), read_only_(read_only) {}
  absl::StatusOr<v1::AddRecordingResponse> Add(const v1::AddRecordingRequest& request);
  absl::StatusOr<v1::GetRecordingResponse> Get(const std::string& hash);
  absl::StatusOr<v1::ListRecordingsResponse> List();
  // OK if every hash names a stored recording; the error names the field path.
  absl::Status CheckExist(const google::protobuf::RepeatedPtrField<std::string>& hashes,
                          const std::string& field);
  // OK if every stored recording of `fields` (name, hashes) is of `robot` and sampled at one
  // rate (within 1%); the error names the first field path that is not, and what it is.
  absl::Status CheckOneRobotAndRate(
      const std::string& robot,
      const std::vector<std::pair<std::string, const google::protobuf::RepeatedPtrField<std::string>*>>&
          fields);

 private:
  storage::StudyStore& store_;
  const size_t max_bytes_;
  const bool read_only_;
};

}  // namespace gaitforge::coordinator
