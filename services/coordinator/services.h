#pragma once
// Thin gRPC adapters over Coordinator: convert, delegate, convert back.
#include "gaitforge/v1/recording.grpc.pb.h"
#include "gaitforge/v1/study.grpc.pb.h"
#include "gaitforge/v1/worker.grpc.pb.h"
#include "services/coordinator/auth.h"
#include "services/coordinator/coordinator.h"

namespace gaitforge::coordinator {

class StudyServiceImpl final : public v1::StudyService::Service {
 public:
  StudyServiceImpl(Coordinator& c, const Auth& auth) : c_(c), auth_(auth) {}
  grpc::Status CreateStudy(grpc::ServerContext*, const v1::CreateStudyRequest*,
                           v1::CreateStudyResponse*) override;
  grpc::Status GetStudy(grpc::ServerContext*, const v1::GetStudyRequest*,
                        v1::StudySummary*) override;
  grpc::Status ListStudies(grpc::ServerContext*, const v1::ListStudiesRequest*,
                           v1::ListStudiesResponse*) override;
  grpc::Status WatchStudy(grpc::ServerContext*, const v1::WatchStudyRequest*,
                          grpc::ServerWriter<v1::Progress>*) override;
  grpc::Status GetHallOfFame(grpc::ServerContext*, const v1::GetHallOfFameRequest*,
                             v1::GetHallOfFameResponse*) override;
  grpc::Status GetHistory(grpc::ServerContext*, const v1::GetHistoryRequest*,
                          v1::GetHistoryResponse*) override;
  grpc::Status ListIndividuals(grpc::ServerContext*, const v1::ListIndividualsRequest*,
                               v1::ListIndividualsResponse*) override;
  grpc::Status ResumeStudy(grpc::ServerContext*, const v1::ResumeStudyRequest*,
                           v1::StudySummary*) override;
  grpc::Status CancelStudy(grpc::ServerContext*, const v1::CancelStudyRequest*,
                           v1::StudySummary*) override;

 private:
  Coordinator& c_;
  const Auth& auth_;
};

// gRPC's callback API: a waiting Lease holds no thread (the coordinator's dispatcher
// answers it), and reports and heartbeats run on gRPC's own threads (issue 30).
class WorkerServiceImpl final : public v1::WorkerService::CallbackService {
 public:
  WorkerServiceImpl(Coordinator& c, const Auth& auth) : c_(c), auth_(auth) {}
  grpc::ServerUnaryReactor* Lease(grpc::CallbackServerContext*, const v1::LeaseRequest*,
                                  v1::LeaseResponse*) override;
  grpc::ServerUnaryReactor* Report(grpc::CallbackServerContext*, const v1::ReportRequest*,
                                   v1::ReportResponse*) override;
  grpc::ServerUnaryReactor* Heartbeat(grpc::CallbackServerContext*, const v1::HeartbeatRequest*,
                                      v1::HeartbeatResponse*) override;
  grpc::ServerUnaryReactor* GetRobot(grpc::CallbackServerContext*, const v1::GetRobotRequest*,
                                     v1::GetRobotResponse*) override;

 private:
  Coordinator& c_;
  const Auth& auth_;
};

class RecordingServiceImpl final : public v1::RecordingService::Service {
 public:
  RecordingServiceImpl(Coordinator& c, const Auth& auth) : c_(c), auth_(auth) {}
  grpc::Status AddRecording(grpc::ServerContext* ctx, const v1::AddRecordingRequest*,
                            v1::AddRecordingResponse*) override;
  grpc::Status GetRecording(grpc::ServerContext* ctx, const v1::GetRecordingRequest*,
                            v1::GetRecordingResponse*) override;
  grpc::Status ListRecordings(grpc::ServerContext* ctx, const v1::ListRecordingsRequest*,
                              v1::ListRecordingsResponse*) override;

 private:
  Coordinator& c_;
  const Auth& auth_;
};

}  // namespace gaitforge::coordinator
