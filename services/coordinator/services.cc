#include "services/coordinator/services.h"

#include <thread>

#include "services/coordinator/grpc_status.h"

namespace gaitforge::coordinator {
namespace {

grpc::Status NeedId(const std::string& id) { return NeedField(id, "study_id"); }

}  // namespace

grpc::Status StudyServiceImpl::CreateStudy(grpc::ServerContext* ctx,
                                           const v1::CreateStudyRequest* req,
                                           v1::CreateStudyResponse* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  auto r = c_.CreateStudy(req->spec());
  if (!r.ok()) return ToGrpc(r.status());
  *out->mutable_study() = std::move(*r);
  return grpc::Status::OK;
}

grpc::Status StudyServiceImpl::GetStudy(grpc::ServerContext* ctx, const v1::GetStudyRequest* req,
                                        v1::StudySummary* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  if (auto s = NeedId(req->study_id()); !s.ok()) return s;
  return Reply(c_.GetStudy(req->study_id()), out);
}

grpc::Status StudyServiceImpl::ListStudies(grpc::ServerContext* ctx, const v1::ListStudiesRequest*,
                                           v1::ListStudiesResponse* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  auto r = c_.ListStudies();
  if (!r.ok()) return ToGrpc(r.status());
  for (auto& s : *r) *out->add_studies() = std::move(s);
  return grpc::Status::OK;
}

grpc::Status StudyServiceImpl::WatchStudy(grpc::ServerContext* ctx,
                                          const v1::WatchStudyRequest* req,
                                          grpc::ServerWriter<v1::Progress>* writer) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  if (auto s = NeedId(req->study_id()); !s.ok()) return s;
  int64_t sent_version = -1;
  std::string sent;  // the last progress sent, serialized
  for (;;) {
    auto p = c_.Progress(req->study_id());
    if (!p.ok()) return ToGrpc(p.status());
    // Another coordinator may own the study (this one reads the file): compare content,
    // not only this process's version.
    // The end of a study is durable before the client hears of it: a script that reads
    // the database when `watch` returns finds every row (writes are otherwise group-
    // committed behind the progress, docs/design.md "Durability").
    if (p->first.state() != v1::STUDY_STATE_RUNNING)
      if (auto f = c_.Flush(); !f.ok()) return ToGrpc(f);
    std::string now = p->first.SerializeAsString();
    if (now != sent) {
      if (!writer->Write(p->first)) return grpc::Status::OK;  // client went away
      sent = std::move(now);
    }
    sent_version = p->second;
    if (p->first.state() != v1::STUDY_STATE_RUNNING) return grpc::Status::OK;
    if (ctx->IsCancelled()) return grpc::Status::CANCELLED;
    // Progress is sent at most every 100 ms, so that fast studies do not flood the stream.
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    c_.WaitForChange(sent_version, 1000);
  }
}

grpc::Status StudyServiceImpl::GetHallOfFame(grpc::ServerContext* ctx,
                                             const v1::GetHallOfFameRequest* req,
                                             v1::GetHallOfFameResponse* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  if (auto s = NeedId(req->study_id()); !s.ok()) return s;
  std::optional<int> g;
  if (req->has_generation()) g = req->generation();
  return Reply(c_.HallOfFame(req->study_id(), g), out);
}

grpc::Status StudyServiceImpl::GetHistory(grpc::ServerContext* ctx, const v1::GetHistoryRequest* req,
                                          v1::GetHistoryResponse* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  if (auto s = NeedId(req->study_id()); !s.ok()) return s;
  return Reply(c_.History(req->study_id()), out);
}

grpc::Status StudyServiceImpl::ListIndividuals(grpc::ServerContext* ctx,
                                               const v1::ListIndividualsRequest* req,
                                               v1::ListIndividualsResponse* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  if (auto s = NeedId(req->study_id()); !s.ok()) return s;
  return Reply(c_.Individuals(req->study_id(), req->generation()), out);
}

grpc::Status StudyServiceImpl::ResumeStudy(grpc::ServerContext* ctx,
                                           const v1::ResumeStudyRequest* req,
                                           v1::StudySummary* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  if (auto s = NeedId(req->study_id()); !s.ok()) return s;
  return Reply(c_.ResumeStudy(req->study_id()), out);
}

grpc::Status StudyServiceImpl::CancelStudy(grpc::ServerContext* ctx,
                                           const v1::CancelStudyRequest* req,
                                           v1::StudySummary* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  if (auto s = NeedId(req->study_id()); !s.ok()) return s;
  return Reply(c_.CancelStudy(req->study_id()), out);
}

namespace {

// A Lease call: finished once, by the coordinator's answer; a caller that goes away marks
// it cancelled so that no jobs are leased to it.
class LeaseReactor final : public grpc::ServerUnaryReactor {
 public:
  explicit LeaseReactor(Coordinator& c) : c_(c) {}
  std::shared_ptr<std::atomic<bool>> cancelled() const { return cancelled_; }
  // The callback that finishes the call with the coordinator's answer into *out.
  template <typename Out>
  std::function<void(absl::StatusOr<Out>)> Answer(Out* out) {
    return [this, out](absl::StatusOr<Out> r) { Finish(Reply(std::move(r), out)); };
  }
  void OnCancel() override {
    cancelled_->store(true);
    c_.WakeLeases();
  }
  void OnDone() override { delete this; }

 private:
  Coordinator& c_;
  std::shared_ptr<std::atomic<bool>> cancelled_ = std::make_shared<std::atomic<bool>>(false);
};

// A callback method answered on the calling thread: the call's result, unless `auth` refused.
template <typename Call, typename Out>
grpc::ServerUnaryReactor* AnswerNow(grpc::CallbackServerContext* ctx, const grpc::Status& auth,
                                    Call call, Out* out) {
  auto* reactor = ctx->DefaultReactor();
  reactor->Finish(auth.ok() ? Reply(call(), out) : auth);
  return reactor;
}

}  // namespace

grpc::ServerUnaryReactor* WorkerServiceImpl::Lease(grpc::CallbackServerContext* ctx,
                                                   const v1::LeaseRequest* req,
                                                   v1::LeaseResponse* out) {
  auto* reactor = new LeaseReactor(c_);
  if (auto a = auth_.Check(ctx, Role::kWorker); !a.ok()) reactor->Finish(a);
  else c_.LeaseAsync(*req, reactor->Answer(out), reactor->cancelled());
  return reactor;
}

grpc::ServerUnaryReactor* WorkerServiceImpl::Report(grpc::CallbackServerContext* ctx,
                                                    const v1::ReportRequest* req,
                                                    v1::ReportResponse* out) {
  const grpc::Status auth = auth_.Check(ctx, Role::kWorker);
  if (!req->has_next() || !auth.ok())
    return AnswerNow(ctx, auth, [&] { return c_.Report(*req); }, out);
  // Report, then lease the next batch in the same call (docs/protocol.md).
  auto* reactor = new LeaseReactor(c_);
  if (const grpc::Status s = Reply(c_.Report(*req), out); !s.ok()) {
    reactor->Finish(s);
    return reactor;
  }
  c_.LeaseAsync(
      req->next(),
      [reactor, out](absl::StatusOr<v1::LeaseResponse> lease) {
        if (lease.ok()) *out->mutable_lease() = std::move(*lease);
        reactor->Finish(grpc::Status::OK);  // the results are recorded whatever the lease
      },
      reactor->cancelled());
  return reactor;
}

grpc::ServerUnaryReactor* WorkerServiceImpl::Heartbeat(grpc::CallbackServerContext* ctx,
                                                       const v1::HeartbeatRequest* req,
                                                       v1::HeartbeatResponse* out) {
  return AnswerNow(ctx, auth_.Check(ctx, Role::kWorker), [&] { return c_.Heartbeat(*req); }, out);
}

grpc::ServerUnaryReactor* WorkerServiceImpl::GetRobot(grpc::CallbackServerContext* ctx,
                                                      const v1::GetRobotRequest* req,
                                                      v1::GetRobotResponse* out) {
  return AnswerNow(ctx, auth_.Check(ctx, Role::kWorker), [&] { return c_.GetRobot(*req); }, out);
}

grpc::Status RecordingServiceImpl::AddRecording(grpc::ServerContext* ctx,
                                                const v1::AddRecordingRequest* req,
                                                v1::AddRecordingResponse* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  return Reply(c_.recordings().Add(*req), out);
}

grpc::Status RecordingServiceImpl::GetRecording(grpc::ServerContext* ctx,
                                                const v1::GetRecordingRequest* req,
                                                v1::GetRecordingResponse* out) {
  if (auto a = auth_.CheckEither(ctx, Role::kClient, Role::kWorker); !a.ok()) return a;
  if (req->hash().empty())
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, "field 'hash' is required");
  return Reply(c_.recordings().Get(req->hash()), out);
}

grpc::Status RecordingServiceImpl::ListRecordings(grpc::ServerContext* ctx,
                                                  const v1::ListRecordingsRequest*,
                                                  v1::ListRecordingsResponse* out) {
  if (auto a = auth_.Check(ctx, Role::kClient); !a.ok()) return a;
  return Reply(c_.recordings().List(), out);
}

}  // namespace gaitforge::coordinator
