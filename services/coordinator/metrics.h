#pragma once
// The coordinator's Prometheus metrics (prometheus-cpp; served as text on its own port by
// main.cc). Names and meanings: docs/metrics.md.
#include <prometheus/counter.h>
#include <prometheus/family.h>
#include <prometheus/gauge.h>
#include <prometheus/histogram.h>
#include <prometheus/registry.h>

#include <memory>
#include <string>

namespace gaitforge::coordinator {

class Metrics {
 public:
  Metrics();
  std::shared_ptr<prometheus::Registry> registry() const { return registry_; }

  void Leased(int jobs, int backups);
  void Expired(int leases, int requeued, int poisoned);
  void Duplicates(int n);
  // outcome: "valid", "invalid" or "poisoned".
  void Evaluated(const std::string& outcome, double seconds);
  void SetQueue(double depth, double in_flight, double workers);
  // After each committed generation; `invalid`: its invalid members.
  void SetStudy(const std::string& study_id, int generations_done, double best, int invalid);
  void Commit(double seconds);

 private:
  std::shared_ptr<prometheus::Registry> registry_;
  prometheus::Gauge* queue_depth_;
  prometheus::Gauge* in_flight_;
  prometheus::Gauge* workers_;
  prometheus::Counter* leases_;
  prometheus::Counter* backups_;
  prometheus::Counter* expiries_;
  prometheus::Counter* retries_;
  prometheus::Counter* poisoned_;
  prometheus::Counter* duplicates_;
  prometheus::Family<prometheus::Counter>* evaluations_;
  prometheus::Histogram* eval_seconds_;
  prometheus::Histogram* commit_seconds_;
  prometheus::Family<prometheus::Gauge>* generation_;
  prometheus::Family<prometheus::Gauge>* best_;
  prometheus::Family<prometheus::Gauge>* invalid_;
};

}  // namespace gaitforge::coordinator
