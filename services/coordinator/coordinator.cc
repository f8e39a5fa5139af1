#include "services/coordinator/coordinator.h"

#include <google/protobuf/util/json_util.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "absl/strings/str_cat.h"
#include "services/coordinator/metrics.h"
#include "services/coordinator/constraints.h"
#include "services/coordinator/from_calibration.h"
#include "services/coordinator/from_diagnosis.h"
#include "services/coordinator/validation.h"
#include "services/spec/engine_kinds.h"
#include "services/spec/spec_validation.h"

namespace gaitforge::coordinator {
namespace {

uint32_t NewEpoch() {
  std::random_device rd;
  uint32_t e = rd();
  return e == 0 ? 1 : e;
}

// The commonest reason among invalid members (the first in byte order among equals, as
// the store's History reads it back) and how many gave it; {"", 0} for none.
std::pair<std::string, int> Commonest(const std::map<std::string, int>& reasons) {
  std::pair<std::string, int> out;
  for (const auto& [reason, n] : reasons)
    if (n > out.second) out = {reason, n};
  return out;
}

// Why a generation in which no member is valid stops its study.
std::string AllInvalidError(int generation, int members,
                            const std::map<std::string, int>& reasons) {
  const auto [reason, n] = Commonest(reasons);
  return absl::StrCat("generation ", generation, ": all ", members,
                      " members are invalid; commonest reason (", n, " of ", members,
                      "): ", reason.empty() ? "none given" : reason);
}

}  // namespace

std::string NewId(const std::string& name) {
  std::string slug;
  for (char c : name) {
    if (std::isalnum(static_cast<unsigned char>(c))) slug += static_cast<char>(std::tolower(c));
    else if (!slug.empty() && slug.back() != '-') slug += '-';
    if (slug.size() >= 32) break;
  }
  while (!slug.empty() && slug.back() == '-') slug.pop_back();
  if (slug.empty()) slug = "study";
  std::random_device rd;
  return absl::StrCat(slug, "-", absl::Hex(rd() & 0xffffff, absl::kZeroPad6));
}

Coordinator::Coordinator(std::unique_ptr<storage::StudyStore> store, CoordinatorOptions options,
                         core::Clock& clock)
    : store_(std::move(store)),
      options_(options),
      recordings_(std::make_unique<Recordings>(*store_, options.max_recording_bytes,
                                               options.read_only)),
      clock_(clock),
      queue_(clock, queue::QueueOptions{options.lease_ms, options.max_attempts,
                                        options.backup_after_ms},
             NewEpoch()) {
  dispatcher_ = std::thread([this] { DispatchLeases(); });
}

Coordinator::~Coordinator() {
  Shutdown();
  if (dispatcher_.joinable()) dispatcher_.join();
}

std::map<std::string, double> MetricsOf(const v1::Evaluation& e) {
  return std::map<std::string, double>(e.metrics().begin(), e.metrics().end());
}

bool Coordinator::Finished(const Study& s) {
  return s.engine->Done() || s.engine->generation() >= s.spec.generations();
}

absl::StatusOr<std::unique_ptr<engines::Engine>> Coordinator::MakeEngine(
    const v1::StudySpec& spec) {
  return spec::MakeEngine(spec);
}

absl::StatusOr<v1::StudySummary> Coordinator::CreateStudy(v1::StudySpec spec) {
  if (options_.read_only)
    return absl::FailedPreconditionError("this coordinator is read-only; it takes no new study");
  const SpreadFn spread = [this](const std::string& id, int g) { return SpreadAfter(id, g); };
  if (auto s = ResolveValidation(*store_, spread, &spec); !s.ok()) return s;
  if (auto s = ResolveFromDiagnosis(*store_, &spec); !s.ok()) return s;
  if (auto s = ResolveFromCalibration(*store_, spread, &spec); !s.ok()) return s;
  spec::ApplyDefaults(&spec);
  if (auto s = spec::ValidationStatus(spec::Validate(spec)); !s.ok()) return s;
  if (auto s = recordings_->CheckExist(spec.objective().recordings(), "objective.recordings");
      !s.ok())
    return s;
  if (auto s = recordings_->CheckExist(spec.objective().held_out(), "objective.held_out"); !s.ok())
    return s;
  auto engine = MakeEngine(spec);
  if (!engine.ok()) return engine.status();

  storage::StudyRecord r;
  r.study_id = NewId(spec.name());
  r.name = spec.name();
  r.spec = spec.SerializeAsString();
  google::protobuf::util::JsonPrintOptions jo;
  jo.preserve_proto_field_names = true;
  (void)google::protobuf::util::MessageToJsonString(spec, &r.spec_json, jo);
  r.state = "running";
  r.generations_total = spec.generations();
  r.created_ms = r.updated_ms = clock_.UnixMs();
  // Durable before the client hears of it.
  if (auto s = store_->CreateStudy(r).get(); !s.ok()) return s;

  std::lock_guard<std::mutex> l(mu_);
  auto study = std::make_unique<Study>();
  study->id = r.study_id;
  study->record = r;
  study->spec = std::move(spec);
  study->engine = std::move(*engine);
  Study& s = *study;
  studies_[r.study_id] = std::move(study);
  spdlog::info("study={} created: {} x {}, objective {}", s.id, s.spec.population(),
               s.spec.generations(), s.spec.objective().name());
  if (Finished(s)) {
    SetState(s, "completed", "");
  } else {
    StartGeneration(s, {});
  }
  Bump();
  return Summarize(s.record);
}

absl::Status Coordinator::RecoverStudies() {
  if (options_.read_only) return absl::OkStatus();
  auto all = store_->ListStudies();
  if (!all.ok()) return all.status();
  for (const auto& r : *all) {
    if (r.state != "running") continue;
    if (auto s = Activate(r); !s.ok()) {
      spdlog::error("study={} cannot resume: {}", r.study_id, std::string(s.message()));
      std::lock_guard<std::mutex> l(mu_);
      WatchWrite(store_->SetStudyState(r.study_id, "failed", std::string(s.message())),
                 r.study_id);
    }
  }
  return absl::OkStatus();
}

absl::Status Coordinator::Activate(const storage::StudyRecord& record) {
  auto study = std::make_unique<Study>();
  study->id = record.study_id;
  study->record = record;
  if (!study->spec.ParseFromString(record.spec))
    return absl::DataLossError("stored spec does not parse");
  auto engine = MakeEngine(study->spec);
  if (!engine.ok()) return engine.status();
  study->engine = std::move(*engine);
  auto latest = store_->LatestEngineState(record.study_id);
  if (!latest.ok()) return latest.status();
  if (*latest) {
    if (auto s = study->engine->LoadState((*latest)->second); !s.ok()) return s;
    if (study->engine->generation() != (*latest)->first + 1)
      return absl::DataLossError("engine state does not match its generation");
  }
  study->evaluations = record.evaluations;
  std::vector<storage::IndividualRecord> stored;
  if (!Finished(*study)) {
    auto rows = store_->Individuals(record.study_id, study->engine->generation());
    if (!rows.ok()) return rows.status();
    stored = std::move(*rows);
  }
  std::lock_guard<std::mutex> l(mu_);
  if (auto it = studies_.find(record.study_id);
      it != studies_.end() && it->second->record.state == "running")
    return absl::OkStatus();  // activated meanwhile (two resumes at once)
  Study& s = *study;
  studies_[record.study_id] = std::move(study);
  if (Finished(s)) {
    SetState(s, "completed", "");
    return absl::OkStatus();
  }
  spdlog::info("study={} resumed at generation={} ({} results already stored)", s.id,
               s.engine->generation(), stored.size());
  StartGeneration(s, stored);
  Bump();
  return absl::OkStatus();
}

void Coordinator::StartGeneration(Study& s, const std::vector<storage::IndividualRecord>& stored) {
  const auto& cands = s.engine->Ask();
  const int g = s.engine->generation();
  s.results.assign(cands.size(), std::nullopt);
  s.remaining = static_cast<int>(cands.size());
  for (const auto& c : cands) {
    if (c.known) {
      Result r;
      r.evaluation.set_valid(c.known->valid);
      r.evaluation.set_fitness(c.known->fitness);
      r.evaluation.set_reason(c.known->reason);
      r.carried = true;
      r.violation = c.known->violation;
      s.results[c.member] = std::move(r);
      --s.remaining;
    }
  }
  // Results committed before a restart are never evaluated again.
  for (const auto& row : stored) {
    if (row.carried || row.member < 0 || row.member >= static_cast<int>(cands.size())) continue;
    if (s.results[row.member] || row.genes != cands[row.member].genes) continue;
    Result r;
    r.evaluation.set_valid(row.valid);
    r.evaluation.set_fitness(row.fitness);
    r.evaluation.set_reason(row.reason);
    for (const auto& [k, v] : row.metrics) (*r.evaluation.mutable_metrics())[k] = v;
    r.worker_id = row.worker_id;
    r.eval_seconds = row.eval_seconds;
    r.violation = Violation(s.spec, row.valid, row.metrics);
    s.results[row.member] = std::move(r);
    --s.remaining;
    ++s.evaluations;
  }
  for (const auto& c : cands) {
    if (!s.results[c.member]) queue_.Add(queue::JobKey{s.id, g, c.member});
  }
  if (s.remaining == 0) {
    CompleteGeneration(s);
    return;
  }
  WakeDispatcher();
}

void Coordinator::Accept(Study& s, int member, Result result,
                         std::vector<storage::IndividualRecord>* out) {
  const auto& cand = s.engine->Ask()[member];
  storage::IndividualRecord row;
  row.study_id = s.id;
  row.generation = s.engine->generation();
  row.member = member;
  row.genes = cand.genes;
  row.valid = result.evaluation.valid();
  row.fitness = result.evaluation.fitness();
  row.reason = result.evaluation.reason();
  for (const auto& [k, v] : result.evaluation.metrics()) row.metrics[k] = v;
  row.worker_id = result.worker_id;
  row.eval_seconds = result.eval_seconds;
  row.origin_generation = row.generation;
  row.origin_member = member;
  row.reported_ms = clock_.UnixMs();
  // A multi-objective study needs every objective's metric: without one the result is
  // invalid, with the reason, rather than ranked on a made-up value.
  std::vector<double> objectives;
  if (auto st = spec::ObjectivesOf(s.spec, result.evaluation, &objectives); !st.ok()) {
    result.evaluation.set_valid(false);
    result.evaluation.set_reason(std::string(st.message()));
    row.valid = false;
    row.reason = result.evaluation.reason();
  }
  result.violation = Violation(s.spec, result.evaluation.valid(), row.metrics);
  row.violation = result.violation;
  out->push_back(std::move(row));
  s.results[member] = std::move(result);
  --s.remaining;
  ++s.evaluations;
  s.rate.emplace_back(clock_.NowMs(), s.evaluations);
  while (s.rate.size() > 2 && s.rate.front().first < clock_.NowMs() - 10000) s.rate.pop_front();
}

void Coordinator::CompleteGeneration(Study& s) {
  const int g = s.engine->generation();
  const auto cands = s.engine->Ask();  // copy: Tell replaces them
  std::vector<engines::Evaluation> evals(cands.size());
  storage::GenerationRecord rec;
  rec.study_id = s.id;
  rec.generation = g;
  double sum = 0, sum2 = 0, best = -INFINITY;
  int valid = 0;
  std::map<std::string, int> invalid_reasons;
  for (size_t m = 0; m < cands.size(); ++m) {
    const Result& r = *s.results[m];
    evals[m] = {r.evaluation.valid(), r.evaluation.fitness(), r.evaluation.reason(), r.violation,
                {}};
    if (!spec::ObjectivesOf(s.spec, r.evaluation, &evals[m].objectives).ok())
      evals[m].valid = false;
    if (r.carried) {
      storage::IndividualRecord row;
      row.study_id = s.id;
      row.generation = g;
      row.member = static_cast<int>(m);
      row.genes = cands[m].genes;
      row.valid = r.evaluation.valid();
      row.fitness = r.evaluation.fitness();
      row.reason = r.evaluation.reason();
      row.carried = true;
      row.violation = r.violation;
      row.origin_generation = cands[m].origin_generation;
      row.origin_member = cands[m].origin_member;
      row.reported_ms = clock_.UnixMs();
      rec.carried.push_back(std::move(row));
    } else {
      ++rec.evaluations;
    }
    if (!r.evaluation.valid()) {
      ++rec.invalid;
      ++invalid_reasons[r.evaluation.reason()];
      continue;
    }
    ++valid;
    sum += r.evaluation.fitness();
    sum2 += r.evaluation.fitness() * r.evaluation.fitness();
    best = std::max(best, r.evaluation.fitness());
  }
  rec.best = valid ? best : NAN;
  rec.mean = valid ? sum / valid : NAN;
  rec.stddev = valid ? std::sqrt(std::max(0.0, sum2 / valid - rec.mean * rec.mean)) : NAN;
  // Diversity: mean over genes of the population's std, in units of the gene's range.
  double div = 0;
  const int n_genes = s.spec.bounds_size();
  for (int i = 0; i < n_genes; ++i) {
    double m1 = 0, m2 = 0;
    for (const auto& c : cands) {
      m1 += c.genes[i];
      m2 += c.genes[i] * c.genes[i];
    }
    m1 /= cands.size();
    const double var = std::max(0.0, m2 / cands.size() - m1 * m1);
    div += std::sqrt(var) / (s.spec.bounds(i).hi() - s.spec.bounds(i).lo());
  }
  rec.diversity = n_genes ? div / n_genes : 0;

  if (auto st = s.engine->Tell(evals); !st.ok()) {
    spdlog::error("study={} engine rejected generation={}: {}", s.id, g, std::string(st.message()));
    queue_.RemoveStudy(s.id);
    SetState(s, "failed", absl::StrCat("engine: ", st.message()));
    return;
  }
  for (const auto& h : s.engine->HallOfFame()) {
    rec.hall_of_fame.push_back(storage::HofRecord{static_cast<int>(rec.hall_of_fame.size()),
                                                  h.generation, h.member, h.genes, h.eval.valid,
                                                  h.eval.fitness});
  }
  rec.engine_state = s.engine->SaveState();
  rec.counters = s.counters;
  s.counters = {};
  rec.committed_ms = clock_.UnixMs();
  rec.study_state = Finished(s) ? "completed" : "running";
  // The study's best is the hall of fame's first (feasible first, Deb's rule), the same
  // number live and after a restart; the generation row keeps its own population stats.
  rec.study_best = rec.hall_of_fame.empty() || !rec.hall_of_fame[0].valid
                       ? std::nullopt
                       : std::optional<double>(rec.hall_of_fame[0].fitness);
  rec.study_evaluations = s.evaluations;

  s.record.generations_done = g + 1;
  s.record.best_fitness = rec.hall_of_fame.empty() || !rec.hall_of_fame[0].valid
                              ? std::nullopt
                              : std::optional<double>(rec.hall_of_fame[0].fitness);
  s.record.mean_fitness = valid ? std::optional<double>(rec.mean) : std::nullopt;
  s.record.evaluations = s.evaluations;
  s.record.state = rec.study_state;
  s.record.updated_ms = rec.committed_ms;
  s.last_invalid = rec.invalid;
  s.last_invalid_reason = Commonest(invalid_reasons).first;
  spdlog::debug("study={} generation={} done: best {} mean {}", s.id, g, rec.best, rec.mean);
  if (options_.metrics)
    options_.metrics->SetStudy(s.id, g + 1, s.record.best_fitness.value_or(NAN), rec.invalid);
  WatchWrite(store_->CommitGeneration(std::move(rec)), s.id);
  queue_.RemoveGeneration(s.id, g);
  Bump();
  if (valid == 0 && !cands.empty()) {
    // Nothing to select from: every later generation would fail the same way, and a
    // "completed" study of invalid members would pass for a result.
    const std::string error = AllInvalidError(g, static_cast<int>(cands.size()), invalid_reasons);
    spdlog::error("study={} failed: {}", s.id, error);
    queue_.RemoveStudy(s.id);
    SetState(s, "failed", error);
    return;
  }
  if (Finished(s)) {
    spdlog::info("study={} completed after {} generations, best fitness {}", s.id, g + 1,
                 s.record.best_fitness.value_or(NAN));
    return;
  }
  if (s.engine->Ask().empty()) {  // an engine with nothing more to ask is done
    SetState(s, "completed", "");
    return;
  }
  StartGeneration(s, {});
}

void Coordinator::SetState(Study& s, const std::string& state, const std::string& error) {
  s.record.state = state;
  s.record.error = error;
  s.record.updated_ms = clock_.UnixMs();
  WatchWrite(store_->SetStudyState(s.id, state, error), s.id);
  Bump();
}

void Coordinator::WatchWrite(std::future<absl::Status> f, const std::string& study_id) {
  writes_.emplace_back(study_id, std::move(f));
}

void Coordinator::Bump() {
  ++version_;
  change_cv_.notify_all();
}

int64_t Coordinator::WaitForChange(int64_t seen, int timeout_ms) {
  std::unique_lock<std::mutex> l(mu_);
  change_cv_.wait_for(l, std::chrono::milliseconds(timeout_ms),
                      [&] { return version_ != seen || shutdown_; });
  return version_;
}

storage::StudyRecord Coordinator::LiveRecord(const Study& s) const {
  storage::StudyRecord r = s.record;
  r.evaluations = s.evaluations;  // includes results of the generation in flight
  return r;
}

absl::StatusOr<storage::StudyRecord> Coordinator::Record(const std::string& id) {
  {
    std::lock_guard<std::mutex> l(mu_);
    auto it = studies_.find(id);
    if (it != studies_.end()) return LiveRecord(*it->second);
  }
  return store_->GetStudy(id);
}

absl::StatusOr<v1::StudySummary> Coordinator::GetStudy(const std::string& id) {
  auto r = Record(id);
  if (!r.ok()) return r.status();
  v1::StudySummary out = Summarize(*r);
  out.set_stop_reason(StopReason(*r));
  return out;
}

std::string Coordinator::StopReason(const storage::StudyRecord& r) {
  if (r.state != "completed") return "";
  if (r.generations_done >= r.generations_total)
    return absl::StrCat("its ", r.generations_total, " generations are done");
  if (!store_->Flush().ok()) return "";  // the last commit may still be in flight
  auto latest = store_->LatestEngineState(r.study_id);
  v1::StudySpec spec;
  if (!latest.ok() || !*latest || !spec.ParseFromString(r.spec)) return "";
  auto engine = MakeEngine(spec);
  if (!engine.ok() || !(*engine)->LoadState((*latest)->second).ok()) return "";
  return (*engine)->StopReason();
}

absl::StatusOr<std::vector<v1::StudySummary>> Coordinator::ListStudies() {
  auto all = store_->ListStudies();
  if (!all.ok()) return all.status();
  std::vector<v1::StudySummary> out;
  std::lock_guard<std::mutex> l(mu_);
  for (const auto& r : *all) {
    auto it = studies_.find(r.study_id);
    out.push_back(Summarize(it != studies_.end() ? LiveRecord(*it->second) : r));
  }
  return out;
}

absl::StatusOr<v1::StudySummary> Coordinator::ResumeStudy(const std::string& id) {
  if (options_.read_only)
    return absl::FailedPreconditionError("this coordinator is read-only; it resumes nothing");
  auto r = Record(id);
  if (!r.ok()) return r.status();
  if (r->state == "completed")
    return absl::FailedPreconditionError(absl::StrCat("study '", id, "' is already completed"));
  {
    std::lock_guard<std::mutex> l(mu_);
    auto it = studies_.find(id);
    if (it != studies_.end() && it->second->record.state == "running") return Summarize(r.value());
    if (it != studies_.end()) studies_.erase(it);
  }
  if (auto s = store_->SetStudyState(id, "running", "").get(); !s.ok()) return s;
  r->state = "running";
  r->error.clear();
  if (auto s = Activate(*r); !s.ok()) return s;
  return GetStudy(id);
}

absl::StatusOr<v1::StudySummary> Coordinator::CancelStudy(const std::string& id) {
  if (options_.read_only)
    return absl::FailedPreconditionError("this coordinator is read-only; it cancels nothing");
  auto r = Record(id);
  if (!r.ok()) return r.status();
  if (r->state == "completed" || r->state == "cancelled")
    return absl::FailedPreconditionError(
        absl::StrCat("study '", id, "' is already ", r->state, "; nothing to cancel"));
  std::future<absl::Status> done;
  {
    std::lock_guard<std::mutex> l(mu_);
    queue_.RemoveStudy(id);
    auto it = studies_.find(id);
    if (it != studies_.end()) {
      it->second->record.state = "cancelled";
      it->second->record.updated_ms = clock_.UnixMs();
    }
    done = store_->SetStudyState(id, "cancelled", "");
    Bump();
  }
  if (auto s = done.get(); !s.ok()) return s;
  return GetStudy(id);
}

absl::Status Coordinator::Flush() { return store_->Flush(); }

absl::StatusOr<v1::GetHallOfFameResponse> Coordinator::HallOfFame(const std::string& id,
                                                                  std::optional<int> generation) {
  if (auto f = store_->Flush(); !f.ok()) return f;
  auto hof = store_->HallOfFame(id, generation);
  if (!hof.ok()) return hof.status();
  v1::GetHallOfFameResponse out;
  out.set_generation(hof->first);
  for (double x : SpreadAfter(id, hof->first)) out.add_spread(x);
  // Each entry's metrics, from the generation it was evaluated in (a robust study's
  // predicted travel and spread among them).
  std::map<int, std::vector<storage::IndividualRecord>> evaluated;
  for (const auto& h : hof->second) {
    auto* e = out.add_entries();
    e->set_rank(h.rank);
    auto* ind = e->mutable_individual();
    ind->set_generation(h.origin_generation);
    ind->set_member(h.origin_member);
    for (double x : h.genes) ind->add_genes(x);
    ind->mutable_evaluation()->set_valid(h.valid);
    ind->mutable_evaluation()->set_fitness(h.fitness);
    if (!evaluated.count(h.origin_generation)) {
      auto rows = store_->Individuals(id, h.origin_generation);
      evaluated[h.origin_generation] = rows.ok() ? *rows : std::vector<storage::IndividualRecord>{};
    }
    for (const auto& row : evaluated[h.origin_generation])
      if (row.member == h.origin_member)
        for (const auto& [k, v] : row.metrics) (*ind->mutable_evaluation()->mutable_metrics())[k] = v;
  }
  return out;
}

std::vector<double> Coordinator::SpreadAfter(const std::string& id, int generation) {
  auto latest = store_->LatestEngineState(id);
  if (!latest.ok() || !*latest || (*latest)->first != generation) return {};
  auto record = store_->GetStudy(id);
  if (!record.ok()) return {};
  v1::StudySpec spec;
  if (!spec.ParseFromString(record->spec)) return {};
  auto engine = MakeEngine(spec);
  if (!engine.ok() || !(*engine)->LoadState((*latest)->second).ok()) return {};
  return (*engine)->Spread();
}

absl::StatusOr<v1::GetHistoryResponse> Coordinator::History(const std::string& id) {
  if (auto f = store_->Flush(); !f.ok()) return f;
  auto gens = store_->History(id);
  if (!gens.ok()) return gens.status();
  v1::GetHistoryResponse out;
  for (const auto& g : *gens) {
    auto* s = out.add_generations();
    s->set_generation(g.generation);
    s->set_best(g.best);
    s->set_mean(g.mean);
    s->set_stddev(g.stddev);
    s->set_diversity(g.diversity);
    s->set_evaluations(g.evaluations);
    s->set_invalid(g.invalid);
    s->set_committed_unix_ms(g.committed_ms);
    s->set_leases(g.counters.leases);
    s->set_lease_expiries(g.counters.lease_expiries);
    s->set_duplicates(g.counters.duplicates);
    s->set_backups(g.counters.backups);
    s->set_poisoned(g.counters.poisoned);
    s->set_invalid_reason(g.invalid_reason);
  }
  return out;
}

absl::StatusOr<v1::ListIndividualsResponse> Coordinator::Individuals(const std::string& id,
                                                                     int generation) {
  if (auto f = store_->Flush(); !f.ok()) return f;
  auto rows = store_->Individuals(id, generation);
  if (!rows.ok()) return rows.status();
  v1::ListIndividualsResponse out;
  for (const auto& r : *rows) {
    auto* ind = out.add_individuals();
    ind->set_generation(r.generation);
    ind->set_member(r.member);
    for (double x : r.genes) ind->add_genes(x);
    ind->mutable_evaluation()->set_valid(r.valid);
    ind->mutable_evaluation()->set_fitness(r.fitness);
    ind->mutable_evaluation()->set_reason(r.reason);
    for (const auto& [k, v] : r.metrics) (*ind->mutable_evaluation()->mutable_metrics())[k] = v;
    ind->set_worker_id(r.worker_id);
    ind->set_eval_seconds(r.eval_seconds);
    ind->set_carried(r.carried);
    ind->set_violation(r.violation);
  }
  return out;
}

absl::StatusOr<std::pair<v1::Progress, int64_t>> Coordinator::Progress(const std::string& id) {
  std::optional<std::pair<v1::Progress, int64_t>> live;
  storage::StudyRecord record;
  {
    std::lock_guard<std::mutex> l(mu_);
    auto it = studies_.find(id);
    if (it != studies_.end()) {
      live = std::make_pair(MakeProgress(it->second.get(), it->second->record), version_);
      record = it->second->record;
    }
  }
  if (live) {
    live->first.set_stop_reason(StopReason(record));
    return *live;
  }
  auto r = store_->GetStudy(id);
  if (!r.ok()) return r.status();
  auto generations = store_->History(id);  // another coordinator's study: its latest row
  v1::Progress p;
  int64_t version;
  {
    std::lock_guard<std::mutex> l(mu_);
    p = MakeProgress(nullptr, *r);
    version = version_;
  }
  if (generations.ok() && !generations->empty()) {
    p.set_invalid(generations->back().invalid);
    p.set_invalid_reason(generations->back().invalid_reason);
  }
  p.set_stop_reason(StopReason(*r));
  return std::make_pair(p, version);
}

}  // namespace gaitforge::coordinator
