#pragma once
// One leased job evaluated: the EvalInput a Job describes, the objective run on it, and the
// result written into the report. Shared by gaitforge-worker and bench/swarm, so that an
// emulated worker's fitness is the real objective's, bit for bit.
#include <map>
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "gaitforge/v1/worker.pb.h"
#include "workers/objectives/ensemble.h"
#include "workers/objectives/objective.h"

namespace gaitforge::worker {

// Recordings fetched for a batch, by hash (a failed fetch keeps its status).
using FetchedRecordings =
    std::map<std::string, absl::StatusOr<std::shared_ptr<const recording::Recording>>>;

// Evaluates `job` with the registry's objective. Every problem (objective not built in, a
// recording not available, genes and bounds of different lengths) is an invalid result with
// a reason, never an error. Recordings the job names must be in `fetched`.
objectives::EvalResult EvaluateJob(const objectives::ObjectiveRegistry& registry,
                                   const v1::Job& job, const FetchedRecordings& fetched);

// The ensemble of a robust evaluation (ObjectiveSpec.robust, validated with the spec).
objectives::EnsembleSpec EnsembleOf(const v1::Robustness& robust);

// Writes an evaluation and its time into a report's result.
void FillResult(v1::JobResult* out, const objectives::EvalResult& r, double eval_seconds);

}  // namespace gaitforge::worker
