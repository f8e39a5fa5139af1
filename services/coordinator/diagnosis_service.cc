#include "services/coordinator/diagnosis_service.h"

#include "services/coordinator/grpc_status.h"

namespace gaitforge::coordinator {
namespace {

grpc::Status NeedId(const std::string& id) { return NeedField(id, "diagnosis_id"); }

}  // namespace

grpc::Status DiagnosisServiceImpl::CreateDiagnosis(grpc::ServerContext* ctx,
                                                   const v1::CreateDiagnosisRequest* req,
                                                   v1::DiagnosisSummary* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  return Reply(d_.Create(req->spec()), out);
}

grpc::Status DiagnosisServiceImpl::GetDiagnosis(grpc::ServerContext* ctx,
                                                const v1::GetDiagnosisRequest* req,
                                                v1::GetDiagnosisResponse* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  if (auto s = NeedId(req->diagnosis_id()); !s.ok()) return s;
  return Reply(d_.Get(req->diagnosis_id(), req->with_files()), out);
}

grpc::Status DiagnosisServiceImpl::ListDiagnoses(grpc::ServerContext* ctx,
                                                 const v1::ListDiagnosesRequest*,
                                                 v1::ListDiagnosesResponse* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  auto r = d_.List();
  if (!r.ok()) return ToGrpc(r.status());
  for (auto& d : *r) *out->add_diagnoses() = std::move(d);
  return grpc::Status::OK;
}

grpc::Status DiagnosisServiceImpl::CancelDiagnosis(grpc::ServerContext* ctx,
                                                   const v1::CancelDiagnosisRequest* req,
                                                   v1::DiagnosisSummary* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  if (auto s = NeedId(req->diagnosis_id()); !s.ok()) return s;
  return Reply(d_.Cancel(req->diagnosis_id()), out);
}

}  // namespace gaitforge::coordinator
