#include "services/coordinator/metrics.h"

namespace gaitforge::coordinator {
namespace {

prometheus::Gauge* MakeGauge(prometheus::Registry& r, const std::string& name,
                             const std::string& help) {
  return &prometheus::BuildGauge().Name(name).Help(help).Register(r).Add({});
}

prometheus::Counter* MakeCounter(prometheus::Registry& r, const std::string& name,
                                 const std::string& help) {
  return &prometheus::BuildCounter().Name(name).Help(help).Register(r).Add({});
}

}  // namespace

Metrics::Metrics() : registry_(std::make_shared<prometheus::Registry>()) {
  auto& r = *registry_;
  queue_depth_ = MakeGauge(r, "gaitforge_queue_depth", "Jobs waiting for a lease");
  in_flight_ = MakeGauge(r, "gaitforge_jobs_in_flight", "Jobs leased and not yet done");
  workers_ = MakeGauge(r, "gaitforge_connected_workers",
                       "Workers heard from within the last lease period");
  leases_ = MakeCounter(r, "gaitforge_leases_total", "Jobs handed to workers");
  backups_ = MakeCounter(r, "gaitforge_backup_leases_total", "Backup copies of stragglers");
  expiries_ = MakeCounter(r, "gaitforge_lease_expiries_total", "Leases that ran out");
  retries_ = MakeCounter(r, "gaitforge_retries_total", "Jobs queued again after a lost lease");
  poisoned_ = MakeCounter(r, "gaitforge_poisoned_jobs_total", "Jobs closed after too many losses");
  duplicates_ = MakeCounter(r, "gaitforge_duplicate_results_total",
                            "Results for jobs already done (acknowledged, not counted)");
  evaluations_ = &prometheus::BuildCounter()
                      .Name("gaitforge_evaluations_total")
                      .Help("Accepted results by outcome (valid, invalid, poisoned)")
                      .Register(r);
  eval_seconds_ = &prometheus::BuildHistogram()
                       .Name("gaitforge_evaluation_duration_seconds")
                       .Help("Time a worker spent on one evaluation")
                       .Register(r)
                       .Add({}, prometheus::Histogram::BucketBoundaries{
                                    0.0001, 0.001, 0.005, 0.01, 0.025, 0.05, 0.1, 0.25, 0.5,
                                    1, 2.5, 5, 10, 30, 60});
  commit_seconds_ = &prometheus::BuildHistogram()
                         .Name("gaitforge_sqlite_commit_seconds")
                         .Help("Time of one SQLite write transaction (group commit)")
                         .Register(r)
                         .Add({}, prometheus::Histogram::BucketBoundaries{
                                      0.0001, 0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05,
                                      0.1, 0.25, 1});
  generation_ = &prometheus::BuildGauge()
                     .Name("gaitforge_study_generations_done")
                     .Help("Generations committed, per study")
                     .Register(r);
  best_ = &prometheus::BuildGauge()
               .Name("gaitforge_study_best_fitness")
               .Help("Best fitness of the hall of fame, per study")
               .Register(r);
  invalid_ = &prometheus::BuildGauge()
                  .Name("gaitforge_study_invalid_members")
                  .Help("Invalid members of the latest committed generation, per study")
                  .Register(r);
  for (const char* o : {"valid", "invalid", "poisoned"}) evaluations_->Add({{"outcome", o}});
}

void Metrics::Leased(int jobs, int backups) {
  leases_->Increment(jobs);
  backups_->Increment(backups);
}

void Metrics::Expired(int leases, int requeued, int poisoned) {
  expiries_->Increment(leases);
  retries_->Increment(requeued);
  poisoned_->Increment(poisoned);
}

void Metrics::Duplicates(int n) { duplicates_->Increment(n); }

void Metrics::Evaluated(const std::string& outcome, double seconds) {
  evaluations_->Add({{"outcome", outcome}}).Increment();
  if (outcome != "poisoned") eval_seconds_->Observe(seconds);
}

void Metrics::SetQueue(double depth, double in_flight, double workers) {
  queue_depth_->Set(depth);
  in_flight_->Set(in_flight);
  workers_->Set(workers);
}

void Metrics::SetStudy(const std::string& study_id, int generations_done, double best,
                       int invalid) {
  generation_->Add({{"study", study_id}}).Set(generations_done);
  best_->Add({{"study", study_id}}).Set(best);
  invalid_->Add({{"study", study_id}}).Set(invalid);
}

void Metrics::Commit(double seconds) { commit_seconds_->Observe(seconds); }

}  // namespace gaitforge::coordinator
