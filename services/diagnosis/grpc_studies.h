// The gap finder's studies on a coordinator reached over gRPC (studies.h).
#pragma once

#include "gaitforge/v1/study.grpc.pb.h"
#include "services/diagnosis/studies.h"

namespace gaitforge::diagnosis {

class GrpcStudies : public Studies {
 public:
  // Each call has `timeout_s` to answer (0: none).
  GrpcStudies(v1::StudyService::StubInterface& stub, double timeout_s)
      : stub_(stub), timeout_s_(timeout_s) {}
  absl::StatusOr<std::vector<v1::StudySummary>> List() override;
  absl::StatusOr<std::string> Create(const v1::StudySpec& spec) override;
  absl::StatusOr<v1::StudySummary> Get(const std::string& id) override;
  absl::StatusOr<v1::GetHallOfFameResponse> HallOfFame(const std::string& id) override;

 private:
  v1::StudyService::StubInterface& stub_;
  double timeout_s_;
};

}  // namespace gaitforge::diagnosis
