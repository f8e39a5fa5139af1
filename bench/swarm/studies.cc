#include "bench/swarm/studies.h"

#include <spdlog/spdlog.h>

#include <thread>

#include "absl/strings/str_cat.h"
#include "gaitforge/v1/study.grpc.pb.h"
#include "services/rpc/channel.h"

namespace gaitforge::swarm {
namespace {

std::unique_ptr<v1::StudyService::Stub> StudyStub(const std::string& target,
                                                  const std::string& token) {
  rpc::ChannelOptions o;
  o.target = target;
  o.token = token;
  o.own_connection = true;
  return v1::StudyService::NewStub(*rpc::MakeChannel(o));
}

std::string StateName(v1::StudyState s) {
  switch (s) {
    case v1::STUDY_STATE_RUNNING: return "running";
    case v1::STUDY_STATE_COMPLETED: return "completed";
    case v1::STUDY_STATE_FAILED: return "failed";
    case v1::STUDY_STATE_CANCELLED: return "cancelled";
    case v1::STUDY_STATE_PAUSED: return "paused";
    default: return "unspecified";
  }
}

// One study's stream, reopened after a failure until the study is no longer running.
std::string WatchOne(const std::string& target, const std::string& token, const std::string& id,
                     WatchTraffic& traffic) {
  auto stub = StudyStub(target, token);
  for (int attempt = 0;; ++attempt) {
    grpc::ClientContext ctx;
    rpc::PrepareCall(ctx, 7 * 24 * 3600.0, token);
    v1::WatchStudyRequest req;
    req.set_study_id(id);
    auto reader = stub->WatchStudy(&ctx, req);
    v1::Progress p;
    std::string state = "running";
    while (reader->Read(&p)) {
      ++traffic.messages;
      traffic.bytes += static_cast<int64_t>(p.ByteSizeLong());
      state = StateName(p.state());
    }
    grpc::Status s = reader->Finish();
    if (state != "running") return state;
    if (s.ok() || s.error_code() == grpc::StatusCode::NOT_FOUND) return state;
    ++traffic.reconnects;
    spdlog::debug("watch {}: {}; reconnecting", id, s.error_message());
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

}  // namespace

absl::StatusOr<std::vector<std::string>> SubmitStudies(const std::string& target,
                                                       const std::string& token,
                                                       const v1::StudySpec& spec, int count) {
  auto stub = StudyStub(target, token);
  std::vector<std::string> ids;
  for (int i = 0; i < count; ++i) {
    v1::CreateStudyRequest req;
    *req.mutable_spec() = spec;
    req.mutable_spec()->set_seed(spec.seed() + static_cast<uint64_t>(i));
    if (count > 1) req.mutable_spec()->set_name(absl::StrCat(spec.name(), "-", i));
    v1::CreateStudyResponse resp;
    grpc::ClientContext ctx;
    rpc::PrepareCall(ctx, 60, token);
    grpc::Status s = stub->CreateStudy(&ctx, req, &resp);
    if (!s.ok())
      return absl::Status(static_cast<absl::StatusCode>(s.error_code()),
                          absl::StrCat("CreateStudy: ", s.error_message()));
    ids.push_back(resp.study().study_id());
  }
  return ids;
}

std::vector<std::string> WatchToEnd(const std::string& target, const std::string& token,
                                    const std::vector<std::string>& ids, WatchTraffic& traffic) {
  std::vector<std::string> states(ids.size());
  std::vector<std::thread> threads;
  for (size_t i = 0; i < ids.size(); ++i)
    threads.emplace_back([&, i] { states[i] = WatchOne(target, token, ids[i], traffic); });
  for (auto& t : threads) t.join();
  return states;
}

}  // namespace gaitforge::swarm
