#include "services/diagnosis/grpc_studies.h"

#include <chrono>
#include <memory>

#include "absl/strings/str_cat.h"

namespace gaitforge::diagnosis {
namespace {

std::unique_ptr<grpc::ClientContext> Context(double timeout_s) {
  auto ctx = std::make_unique<grpc::ClientContext>();
  if (timeout_s > 0)
    ctx->set_deadline(std::chrono::system_clock::now() +
                      std::chrono::milliseconds(static_cast<int64_t>(timeout_s * 1000)));
  return ctx;
}

absl::Status FromGrpc(const grpc::Status& s, const std::string& what) {
  return absl::Status(static_cast<absl::StatusCode>(s.error_code()),
                      absl::StrCat(what, ": ", s.error_message()));
}

}  // namespace

absl::StatusOr<std::vector<v1::StudySummary>> GrpcStudies::List() {
  v1::ListStudiesResponse resp;
  const grpc::Status s = stub_.ListStudies(Context(timeout_s_).get(), {}, &resp);
  if (!s.ok()) return FromGrpc(s, "list studies");
  return std::vector<v1::StudySummary>(resp.studies().begin(), resp.studies().end());
}

absl::StatusOr<std::string> GrpcStudies::Create(const v1::StudySpec& spec) {
  v1::CreateStudyRequest req;
  *req.mutable_spec() = spec;
  v1::CreateStudyResponse resp;
  const grpc::Status s = stub_.CreateStudy(Context(timeout_s_).get(), req, &resp);
  if (!s.ok()) return FromGrpc(s, "create study " + spec.name());
  return resp.study().study_id();
}

absl::StatusOr<v1::StudySummary> GrpcStudies::Get(const std::string& id) {
  v1::GetStudyRequest req;
  req.set_study_id(id);
  v1::StudySummary resp;
  const grpc::Status s = stub_.GetStudy(Context(timeout_s_).get(), req, &resp);
  if (!s.ok()) return FromGrpc(s, "study " + id);
  return resp;
}

absl::StatusOr<v1::GetHallOfFameResponse> GrpcStudies::HallOfFame(const std::string& id) {
  v1::GetHallOfFameRequest req;
  req.set_study_id(id);
  v1::GetHallOfFameResponse resp;
  const grpc::Status s = stub_.GetHallOfFame(Context(timeout_s_).get(), req, &resp);
  if (!s.ok()) return FromGrpc(s, "hall of fame of " + id);
  return resp;
}

}  // namespace gaitforge::diagnosis
