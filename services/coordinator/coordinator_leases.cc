// Leases: a worker's call for jobs, answered at once when jobs are there, else parked as a
// waiter that the dispatcher thread answers when jobs arrive or its wait ends (issue 30:
// with a thread per waiting call, a new generation woke a thousand threads that took the
// mutex one after another).
#include <pthread.h>
#include <spdlog/spdlog.h>

#include <algorithm>

#include "absl/strings/str_cat.h"
#include "services/coordinator/coordinator.h"
#include "services/recording/recording.h"
#include "services/coordinator/metrics.h"

namespace gaitforge::coordinator {
namespace {

constexpr int kMaxJobsPerLease = 1024;
constexpr int kMaxWaitMs = 10000;
// The dispatcher answers waiters in groups of this many.
constexpr size_t kDeliverGroup = 16;

absl::Status CheckLease(const v1::LeaseRequest& req) {
  if (auto s = CheckWorker(req.worker()); !s.ok()) return s;
  if (req.max_jobs() < 1 || req.max_jobs() > kMaxJobsPerLease)
    return absl::InvalidArgumentError(absl::StrCat(
        "field 'max_jobs' = ", req.max_jobs(), " is out of range [1, ", kMaxJobsPerLease, "]"));
  if (req.wait_ms() < 0 || req.wait_ms() > kMaxWaitMs)
    return absl::InvalidArgumentError(absl::StrCat("field 'wait_ms' = ", req.wait_ms(),
                                                   " is out of range [0, ", kMaxWaitMs, "]"));
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<v1::LeaseResponse> Coordinator::Lease(const v1::LeaseRequest& req) {
  std::promise<absl::StatusOr<v1::LeaseResponse>> answer;
  auto f = answer.get_future();
  LeaseAsync(req, [&answer](absl::StatusOr<v1::LeaseResponse> r) { answer.set_value(std::move(r)); });
  return f.get();
}

void Coordinator::LeaseAsync(const v1::LeaseRequest& req, LeaseDone done,
                             std::shared_ptr<std::atomic<bool>> cancelled) {
  if (auto s = CheckLease(req); !s.ok()) return done(s);
  Waiter w;
  w.worker_id = req.worker().worker_id();
  w.build = req.worker().sim_build();
  w.objectives = {req.worker().objectives().begin(), req.worker().objectives().end()};
  w.max_jobs = req.max_jobs();
  w.deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(req.wait_ms());
  w.done = std::move(done);
  w.cancelled = std::move(cancelled);
  std::optional<Delivery> now;
  {
    std::lock_guard<std::mutex> l(mu_);
    Touch(w.worker_id);
    now = TryServe(w, req.wait_ms() == 0 || shutdown_);
    if (!now) {
      if (w.deadline < next_deadline_) {  // the dispatcher would sleep past it
        recheck_ = true;
        work_cv_.notify_all();
      }
      waiters_.push_back(std::move(w));
    }
  }
  if (now) Deliver(std::move(*now));
}

std::optional<Coordinator::Delivery> Coordinator::TryServe(Waiter& w, bool final) {
  bool refused_build = false;  // jobs were there, but of a study pinned to another build
  auto accept = [&](const queue::JobKey& k) {
    auto it = studies_.find(k.study_id);
    if (it == studies_.end() || it->second->record.state != "running") return false;
    if (!w.objectives.empty() && !w.objectives.count(it->second->spec.objective().name()))
      return false;
    const std::string& pinned = it->second->record.sim_build;
    if (!pinned.empty() && pinned != w.build) {
      refused_build = true;
      return false;
    }
    return true;
  };
  auto leases = queue_.LeaseJobs(w.worker_id, FairShare(w.worker_id, w.max_jobs), accept);
  if (leases.empty() && !final) return std::nullopt;
  Delivery d;
  d.done = std::move(w.done);
  if (leases.empty() && refused_build) {
    d.error = absl::FailedPreconditionError(absl::StrCat(
        "simulator build '", w.build, "' of worker '", w.worker_id,
        "' differs from the build the studies' results come from; run workers of that build"));
    return d;
  }
  d.lease_ms = queue_.lease_ms();
  d.granted = Grant(leases, w.worker_id, w.build);
  return d;
}

std::vector<Coordinator::Granted> Coordinator::Grant(const std::vector<queue::Lease>& leases,
                                                     const std::string& worker_id,
                                                     const std::string& build) {
  if (options_.metrics) {
    int backups = 0;
    for (const auto& lease : leases) backups += lease.backup;
    options_.metrics->Leased(static_cast<int>(leases.size()), backups);
  }
  std::vector<Granted> granted;
  granted.reserve(leases.size());
  for (const auto& lease : leases) {
    Study& s = *studies_.at(lease.key.study_id);
    if (s.record.sim_build.empty() && !build.empty()) {
      // The first lease pins the study to this simulator build.
      s.record.sim_build = build;
      WatchWrite(store_->SetStudySimBuild(s.id, build), s.id);
    }
    ++s.counters.leases;
    if (lease.backup) ++s.counters.backups;
    if (!lease.backup) {
      if (s.part_generation != lease.key.generation) {
        s.part_generation = lease.key.generation;
        s.leased_by_worker.clear();
      }
      ++s.leased_by_worker[worker_id];
    }
    if (!s.context) {
      auto ctx = std::make_shared<v1::StudyContext>();
      ctx->set_study_id(s.id);
      *ctx->mutable_objective() = s.spec.objective();
      *ctx->mutable_bounds() = s.spec.bounds();
      // The descriptor goes by content hash: a worker fetches its text once (GetRobot),
      // rather than in every lease.
      if (v1::ObjectiveSpec* o = ctx->mutable_objective(); !o->robot_descriptor().empty()) {
        const std::string hash = recording::ContentHash(o->robot_descriptor(), "");
        robot_texts_.emplace(hash, o->robot_descriptor());
        o->set_robot_descriptor_hash(hash);
        o->clear_robot_descriptor();
      }
      s.context = std::move(ctx);
    }
    granted.push_back({lease, s.context, s.engine->Ask()[lease.key.member].genes});
  }
  return granted;
}

void Coordinator::Deliver(Delivery d) {
  if (!d.error.ok()) return d.done(d.error);
  v1::LeaseResponse out;
  out.set_lease_ms(static_cast<int32_t>(d.lease_ms));
  std::vector<const v1::StudyContext*> sent;  // one context per study (a lease holds few)
  for (const Granted& g : d.granted) {
    if (std::find(sent.begin(), sent.end(), g.context.get()) == sent.end()) {
      sent.push_back(g.context.get());
      *out.add_studies() = *g.context;
    }
    auto* job = out.add_jobs();
    job->mutable_key()->set_study_id(g.lease.key.study_id);
    job->mutable_key()->set_generation(g.lease.key.generation);
    job->mutable_key()->set_member(g.lease.key.member);
    job->mutable_genes()->Add(g.genes.begin(), g.genes.end());
    job->set_lease_id(g.lease.lease_id);
    job->set_backup(g.lease.backup);
  }
  d.done(std::move(out));
}

void Coordinator::WakeDispatcher() {
  wake_ = true;
  work_cv_.notify_all();
}

void Coordinator::WakeLeases() {
  std::lock_guard<std::mutex> l(mu_);
  recheck_ = true;
  work_cv_.notify_all();
}

void Coordinator::DeliverUnlocked(std::unique_lock<std::mutex>& l, std::vector<Delivery>& ready) {
  if (ready.empty()) return;
  l.unlock();
  for (auto& d : ready) Deliver(std::move(d));
  ready.clear();
  l.lock();
}

void Coordinator::DispatchLeases() {
  pthread_setname_np(pthread_self(), "lease-dispatch");  // for top -H and perf
  std::unique_lock<std::mutex> l(mu_);
  for (;;) {
    next_deadline_ = std::chrono::steady_clock::now() + std::chrono::seconds(1);
    for (const Waiter& w : waiters_) next_deadline_ = std::min(next_deadline_, w.deadline);
    work_cv_.wait_until(l, next_deadline_, [&] { return wake_ || recheck_ || shutdown_; });
    // Jobs arrived: every waiter tries. Otherwise only those whose wait ended or whose
    // caller went away (a pass over a thousand waiters per new waiter cost ~5% of the
    // coordinator's CPU and held the mutex that reports need).
    const bool jobs = wake_ || shutdown_;
    wake_ = recheck_ = false;
    const auto now = std::chrono::steady_clock::now();
    std::vector<Delivery> ready;
    // Waiters in arrival order, so that a generation goes to the longest waiting first,
    // answered in small groups so that the first are on their way while the rest are
    // decided (std::list: LeaseAsync may append while the mutex is released).
    for (auto it = waiters_.begin(); it != waiters_.end();) {
      std::optional<Delivery> d;
      if (it->cancelled && it->cancelled->load())  // the caller is gone: lease it nothing
        d = Delivery{std::move(it->done), absl::CancelledError("the call was cancelled")};
      else if (jobs || now >= it->deadline)
        d = TryServe(*it, shutdown_ || now >= it->deadline);
      if (!d) {
        ++it;
        continue;
      }
      ready.push_back(std::move(*d));
      it = waiters_.erase(it);
      if (ready.size() >= kDeliverGroup) DeliverUnlocked(l, ready);
    }
    const bool stop = shutdown_;
    DeliverUnlocked(l, ready);
    if (stop && waiters_.empty()) return;
  }
}

}  // namespace gaitforge::coordinator
