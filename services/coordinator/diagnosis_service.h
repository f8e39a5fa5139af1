#pragma once
// The DiagnosisService's gRPC adapter over Diagnoses: convert, delegate, convert back.
#include "gaitforge/v1/diagnosis.grpc.pb.h"
#include "services/coordinator/auth.h"
#include "services/coordinator/diagnoses.h"

namespace gaitforge::coordinator {

class DiagnosisServiceImpl final : public v1::DiagnosisService::Service {
 public:
  DiagnosisServiceImpl(Diagnoses& d, const Auth& auth) : d_(d), auth_(auth) {}
  grpc::Status CreateDiagnosis(grpc::ServerContext*, const v1::CreateDiagnosisRequest*,
                               v1::DiagnosisSummary*) override;
  grpc::Status GetDiagnosis(grpc::ServerContext*, const v1::GetDiagnosisRequest*,
                            v1::GetDiagnosisResponse*) override;
  grpc::Status ListDiagnoses(grpc::ServerContext*, const v1::ListDiagnosesRequest*,
                             v1::ListDiagnosesResponse*) override;
  grpc::Status CancelDiagnosis(grpc::ServerContext*, const v1::CancelDiagnosisRequest*,
                               v1::DiagnosisSummary*) override;

 private:
  Diagnoses& d_;
  const Auth& auth_;
};

}  // namespace gaitforge::coordinator
