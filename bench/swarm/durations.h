#pragma once
// How long an emulated evaluation takes: a distribution from the command line, drawn as a
// pure function of the job's key (so a rerun draws the same times).
#include <string>

#include "absl/status/statusor.h"
#include "gaitforge/v1/worker.pb.h"

namespace gaitforge::swarm {

class Durations {
 public:
  // "constant:S" (S seconds), or "lognormal:MEAN:SIGMA" (mean MEAN seconds; SIGMA, the
  // log's standard deviation, sets the tail: 1.0 puts p99 near 6x the mean).
  static absl::StatusOr<Durations> Parse(const std::string& text);
  // Seconds for this job (a backup copy draws the same time as the original).
  double Draw(const v1::JobKey& key) const;
  double mean() const { return mean_; }

 private:
  bool lognormal_ = false;
  double mean_ = 0.5, sigma_ = 0;
};

}  // namespace gaitforge::swarm
