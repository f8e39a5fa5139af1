// The worker side of the coordinator: leases, reports, heartbeats, lease expiry.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "services/coordinator/coordinator.h"
#include "services/recording/recording.h"
#include "services/spec/engine_kinds.h"
#include "services/coordinator/metrics.h"

namespace gaitforge::coordinator {
namespace {

std::string KeyText(const v1::JobKey& k) {
  return absl::StrCat("(study '", k.study_id(), "', generation ", k.generation(), ", member ",
                      k.member(), ")");
}

}  // namespace

absl::Status CheckWorker(const v1::WorkerInfo& w) {
  if (w.worker_id().empty() || w.worker_id().size() > 256)
    return absl::InvalidArgumentError("field 'worker.worker_id' must have 1..256 characters");
  return absl::OkStatus();
}

void Coordinator::Touch(const std::string& worker_id) {
  const int64_t now = clock_.NowMs();
  auto [it, added] = workers_seen_.try_emplace(worker_id, now);
  // A new or returning worker changes the active count at once; otherwise it is recounted
  // at most every kActiveRecountMs (a count over a thousand workers per Lease was the
  // coordinator's largest cost at scale).
  if (added || now - it->second > queue_.lease_ms()) active_at_ms_ = -1;
  it->second = now;
}

int64_t Coordinator::ActiveWorkers() {
  constexpr int64_t kActiveRecountMs = 50;
  const int64_t now = clock_.NowMs();
  if (active_at_ms_ < 0 || now - active_at_ms_ >= kActiveRecountMs || now < active_at_ms_) {
    active_ = 0;
    for (const auto& [id, seen] : workers_seen_) active_ += now - seen <= queue_.lease_ms();
    active_at_ms_ = now;
  }
  return active_;
}

int Coordinator::FairShare(const std::string& worker_id, int requested) {
  // Split what is pending evenly among the active workers that hold no lease yet (those
  // that do already have their share), so that one fast worker does not take a whole
  // generation while others wait, and so that the workers woken by a new generation each
  // get an equal batch instead of ever smaller ones (issue 30).
  const int64_t active = ActiveWorkers();
  const int64_t idle =
      std::max<int64_t>(1, active - static_cast<int64_t>(queue_.workers_holding()));
  const int64_t pending = static_cast<int64_t>(queue_.pending());
  const int64_t share = std::max<int64_t>(1, (pending + idle - 1) / idle);
  return static_cast<int>(std::min<int64_t>({requested, share, PartLeft(worker_id, active)}));
}

int64_t Coordinator::PartLeft(const std::string& worker_id, int64_t active) {
  // The idle workers' share alone misjudges the end of a generation: the first workers
  // back find few idle peers and took up to a whole batch of what was left, while the
  // others, a moment from done, then waited (with 8 jobs per worker a generation took
  // 3 s for 2 s of work at 1,024 workers). A worker's part of the current generations
  // is an even split among all active workers; past it, one job at a time.
  int64_t jobs = 0, mine = 0;
  for (const auto& [id, s] : studies_) {
    if (s->record.state != "running" || Finished(*s)) continue;
    jobs += static_cast<int64_t>(s->engine->Ask().size());
    if (s->part_generation != s->engine->generation()) continue;
    if (auto it = s->leased_by_worker.find(worker_id); it != s->leased_by_worker.end())
      mine += it->second;
  }
  const int64_t part = (jobs + std::max<int64_t>(1, active) - 1) / std::max<int64_t>(1, active);
  return std::max<int64_t>(1, part - mine);
}

absl::StatusOr<v1::ReportResponse> Coordinator::Report(const v1::ReportRequest& req) {
  if (auto s = CheckWorker(req.worker()); !s.ok()) return s;
  std::lock_guard<std::mutex> l(mu_);
  Touch(req.worker().worker_id());
  // Check everything first: all or nothing.
  enum class Fate { kAccept, kDuplicate };
  std::vector<Fate> fate;
  std::vector<std::string> invalid, not_held;
  std::set<std::tuple<std::string, int, int>> seen;
  for (const auto& r : req.results()) {
    const auto& k = r.key();
    const auto& e = r.evaluation();
    if (e.valid() && !std::isfinite(e.fitness())) {
      invalid.push_back(absl::StrCat(KeyText(k), ": field 'evaluation.fitness' = ", e.fitness(),
                                     " must be finite when valid (report valid = false and a "
                                     "reason instead)"));
      continue;
    }
    if (!seen.insert({k.study_id(), k.generation(), k.member()}).second) {
      invalid.push_back(absl::StrCat(KeyText(k), ": reported twice in one call"));
      continue;
    }
    auto it = studies_.find(k.study_id());
    if (it == studies_.end()) {
      // Work leased by an earlier coordinator process for a study this one does not run
      // (finished or cancelled meanwhile): acknowledged, not counted.
      if (r.lease_id() != 0 && (r.lease_id() >> 32) != queue_.epoch()) {
        fate.push_back(Fate::kDuplicate);
        continue;
      }
      not_held.push_back(absl::StrCat(KeyText(k), ": no such study is scheduled here"));
      continue;
    }
    const Study& s = *it->second;
    if (!s.record.sim_build.empty() && s.record.sim_build != req.worker().sim_build()) {
      not_held.push_back(absl::StrCat(KeyText(k), ": simulator build '", req.worker().sim_build(),
                                      "' differs from the study's '", s.record.sim_build, "'"));
      continue;
    }
    const int g = Finished(s) ? s.record.generations_total : s.engine->generation();
    if (k.generation() < g || s.record.state != "running") {
      fate.push_back(Fate::kDuplicate);  // its generation is already committed
      continue;
    }
    if (k.generation() > g || k.member() < 0 ||
        k.member() >= static_cast<int>(s.engine->Ask().size())) {
      not_held.push_back(absl::StrCat(KeyText(k), ": no such job"));
      continue;
    }
    if (s.results[k.member()]) {
      // Done, perhaps stored before a restart (then it is not in this process's queue):
      // a report sent again after its call failed lands here.
      fate.push_back(Fate::kDuplicate);
      continue;
    }
    switch (queue_.Check(req.worker().worker_id(),
                         queue::JobKey{k.study_id(), k.generation(), k.member()}, r.lease_id())) {
      case queue::ReportCheck::kOpen:
        fate.push_back(Fate::kAccept);
        break;
      case queue::ReportCheck::kDone:
        fate.push_back(Fate::kDuplicate);
        break;
      case queue::ReportCheck::kNotHeld:
      case queue::ReportCheck::kUnknown:
        not_held.push_back(absl::StrCat(KeyText(k), ": worker '", req.worker().worker_id(),
                                        "' does not hold this job (lease_id ", r.lease_id(),
                                        ")"));
        break;
    }
  }
  if (!invalid.empty())
    return absl::InvalidArgumentError(
        absl::StrCat("report refused, nothing recorded: ", absl::StrJoin(invalid, "; ")));
  if (!not_held.empty())
    return absl::FailedPreconditionError(
        absl::StrCat("report refused, nothing recorded: ", absl::StrJoin(not_held, "; ")));

  v1::ReportResponse out;
  std::map<std::string, std::vector<storage::IndividualRecord>> rows;
  std::set<std::string> finished;
  int64_t batch_ms = -1;
  for (int i = 0; i < req.results_size(); ++i) {
    const auto& r = req.results(i);
    const auto& k = r.key();
    if (fate[i] == Fate::kDuplicate) {
      out.set_duplicates(out.duplicates() + 1);
      queue_.CountDuplicate();
      if (options_.metrics) options_.metrics->Duplicates(1);
      if (auto it = studies_.find(k.study_id()); it != studies_.end())
        ++it->second->counters.duplicates;
      continue;
    }
    // Only leases still alive measure the batch time: a stalled worker's late result would
    // stretch every lease.
    if (const int64_t age = queue_.LeaseAgeMs(r.lease_id()); age <= queue_.lease_ms())
      batch_ms = std::max<int64_t>(batch_ms, age);
    Study& s = *studies_.at(k.study_id());
    queue_.Complete(queue::JobKey{k.study_id(), k.generation(), k.member()});
    Result res;
    res.evaluation = r.evaluation();
    if (!res.evaluation.valid()) res.evaluation.set_fitness(0);
    res.worker_id = req.worker().worker_id();
    res.eval_seconds = r.eval_seconds();
    if (options_.metrics)
      options_.metrics->Evaluated(r.evaluation().valid() ? "valid" : "invalid", r.eval_seconds());
    Accept(s, k.member(), std::move(res), &rows[s.id]);
    out.set_accepted(out.accepted() + 1);
    if (s.remaining == 0) finished.insert(s.id);
  }
  for (auto& [id, batch] : rows) WatchWrite(store_->AppendResults(std::move(batch)), id);
  for (const auto& id : finished) CompleteGeneration(*studies_.at(id));
  if (batch_ms >= 0) {
    // Leases last about 5x the observed batch time, never less than the configured floor.
    batch_ms_ewma_ = batch_ms_ewma_ == 0 ? batch_ms : 0.8 * batch_ms_ewma_ + 0.2 * batch_ms;
    queue_.set_lease_ms(std::clamp<int64_t>(static_cast<int64_t>(5 * batch_ms_ewma_),
                                            options_.lease_ms, 3600000));
  }
  // What one job takes a worker, for the queue's straggler test (JobQueue::set_job_ms).
  for (const auto& r : req.results()) {
    if (r.eval_seconds() <= 0) continue;
    const double ms = 1000 * r.eval_seconds();
    job_ms_ewma_ = job_ms_ewma_ == 0 ? ms : 0.9 * job_ms_ewma_ + 0.1 * ms;
  }
  queue_.set_job_ms(job_ms_ewma_);
  if (out.accepted() > 0) Bump();
  return out;
}

absl::StatusOr<v1::HeartbeatResponse> Coordinator::Heartbeat(const v1::HeartbeatRequest& req) {
  if (auto s = CheckWorker(req.worker()); !s.ok()) return s;
  std::lock_guard<std::mutex> l(mu_);
  Touch(req.worker().worker_id());
  v1::HeartbeatResponse out;
  out.set_leases_renewed(queue_.Heartbeat(req.worker().worker_id()));
  out.set_lease_ms(static_cast<int32_t>(queue_.lease_ms()));
  return out;
}

absl::StatusOr<v1::GetRobotResponse> Coordinator::GetRobot(const v1::GetRobotRequest& req) {
  if (req.hash().empty()) return absl::InvalidArgumentError("field 'hash' is required");
  std::lock_guard<std::mutex> l(mu_);
  auto it = robot_texts_.find(req.hash());
  if (it == robot_texts_.end()) {
    // Leased by an earlier coordinator process: the studies' specs hold every descriptor.
    for (const auto& [id, s] : studies_) {
      const std::string& text = s->spec.objective().robot_descriptor();
      if (!text.empty()) robot_texts_.emplace(recording::ContentHash(text, ""), text);
    }
    it = robot_texts_.find(req.hash());
  }
  if (it == robot_texts_.end())
    return absl::NotFoundError(
        absl::StrCat("no study here has a robot descriptor of hash '", req.hash(), "'"));
  v1::GetRobotResponse out;
  out.set_text(it->second);
  return out;
}

void Coordinator::Tick() {
  std::lock_guard<std::mutex> l(mu_);
  const auto expiry = queue_.ExpireLeases();
  std::map<std::string, std::vector<storage::IndividualRecord>> rows;
  std::set<std::string> finished;
  for (const auto& key : expiry.expired) {
    if (auto it = studies_.find(key.study_id); it != studies_.end())
      ++it->second->counters.lease_expiries;
  }
  if (options_.metrics) {
    const int poisoned = static_cast<int>(expiry.poisoned.size());
    const int expired = static_cast<int>(expiry.expired.size());
    options_.metrics->Expired(expired, expiry.requeued, poisoned);
  }
  for (const auto& key : expiry.poisoned) {
    auto it = studies_.find(key.study_id);
    if (it == studies_.end()) continue;
    Study& s = *it->second;
    if (s.engine->generation() != key.generation || s.results[key.member]) continue;
    spdlog::warn("study={} generation={} member={} poisoned after {} lost leases", s.id,
                 key.generation, key.member, options_.max_attempts);
    ++s.counters.poisoned;
    Result res;
    res.evaluation.set_valid(false);
    res.evaluation.set_reason(absl::StrCat("poisoned: ", options_.max_attempts,
                                           " leases expired without a result"));
    if (options_.metrics) options_.metrics->Evaluated("poisoned", 0);
    Accept(s, key.member, std::move(res), &rows[s.id]);
    if (s.remaining == 0) finished.insert(s.id);
  }
  for (auto& [id, batch] : rows) WatchWrite(store_->AppendResults(std::move(batch)), id);
  for (const auto& id : finished) CompleteGeneration(*studies_.at(id));
  if (queue_.pending() > 0) WakeDispatcher();
  // Forget workers silent for ten lease periods (restarted workers get new ids).
  const int64_t now = clock_.NowMs();
  std::erase_if(workers_seen_,
                [&](const auto& kv) { return now - kv.second > 10 * queue_.lease_ms(); });
  active_at_ms_ = -1;
  if (options_.metrics) {
    options_.metrics->SetQueue(queue_.pending(), queue_.in_flight(),
                               static_cast<double>(ActiveWorkers()));
  }
  // Surface failed writes: the study stops rather than run on with a hole in its record.
  for (auto it = writes_.begin(); it != writes_.end();) {
    if (it->second.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
      ++it;
      continue;
    }
    absl::Status s = it->second.get();
    if (!s.ok()) {
      spdlog::error("study={} write failed: {}", it->first, std::string(s.message()));
      auto st = studies_.find(it->first);
      if (st != studies_.end() && st->second->record.state == "running") {
        queue_.RemoveStudy(it->first);
        st->second->record.state = "failed";
        st->second->record.error = absl::StrCat("storage: ", s.message());
        Bump();
      }
    }
    it = writes_.erase(it);
  }
}

void Coordinator::Shutdown() {
  {
    std::lock_guard<std::mutex> l(mu_);
    shutdown_ = true;
    WakeDispatcher();  // answers every waiting lease, then stops
  }
  change_cv_.notify_all();
  (void)store_->Flush();  // every write accepted so far is committed
}

queue::QueueCounters Coordinator::QueueStats() {
  std::lock_guard<std::mutex> l(mu_);
  return queue_.counters();
}

v1::StudySummary Coordinator::Summarize(const storage::StudyRecord& r) const {
  v1::StudySummary out;
  out.set_study_id(r.study_id);
  out.mutable_spec()->ParseFromString(r.spec);
  static const std::map<std::string, v1::StudyState> states = {
      {"running", v1::STUDY_STATE_RUNNING},     {"paused", v1::STUDY_STATE_PAUSED},
      {"cancelled", v1::STUDY_STATE_CANCELLED}, {"completed", v1::STUDY_STATE_COMPLETED},
      {"failed", v1::STUDY_STATE_FAILED}};
  auto it = states.find(r.state);
  out.set_state(it == states.end() ? v1::STUDY_STATE_UNSPECIFIED : it->second);
  // A read-only coordinator runs nothing, so a study stored as running is held by no one here.
  if (options_.read_only && out.state() == v1::STUDY_STATE_RUNNING)
    out.set_state(v1::STUDY_STATE_INTERRUPTED);
  out.set_generations_done(r.generations_done);
  out.set_best_fitness(r.best_fitness.value_or(NAN));
  out.set_mean_fitness(r.mean_fitness.value_or(NAN));
  out.set_evaluations(r.evaluations);
  out.set_created_unix_ms(r.created_ms);
  out.set_updated_unix_ms(r.updated_ms);
  out.set_error(r.error);
  out.set_db_path(options_.db_path);
  out.set_sim_build(r.sim_build);
  return out;
}

v1::Progress Coordinator::MakeProgress(const Study* s, const storage::StudyRecord& r) const {
  v1::Progress p;
  const v1::StudySummary sum = Summarize(r);
  p.set_study_id(r.study_id);
  p.set_state(sum.state());
  p.set_generations_done(r.generations_done);
  p.set_generations_total(r.generations_total);
  p.set_best(sum.best_fitness());
  p.set_mean(sum.mean_fitness());
  p.set_evaluations(s ? s->evaluations : r.evaluations);
  p.set_error(r.error);
  if (s) {
    p.set_invalid(s->last_invalid);
    p.set_invalid_reason(s->last_invalid_reason);
  }
  if (s && s->rate.size() >= 2) {
    const auto& [t0, e0] = s->rate.front();
    const auto& [t1, e1] = s->rate.back();
    const double rate = t1 > t0 ? 1000.0 * static_cast<double>(e1 - e0) / (t1 - t0) : 0.0;
    p.set_evals_per_second(rate);
    const int pop = static_cast<int>(s->engine->Ask().size());
    const spec::EngineKind* kind = spec::FindEngineKind(s->spec.engine());
    const int per_gen = kind ? kind->evaluations_per_generation(s->spec, pop) : std::max(1, pop);
    const double left = static_cast<double>(r.generations_total - r.generations_done) * per_gen;
    if (rate > 0 && r.state == "running") p.set_eta_seconds(left / rate);
  }
  return p;
}

}  // namespace gaitforge::coordinator
