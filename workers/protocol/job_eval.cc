#include "workers/protocol/job_eval.h"

#include "absl/strings/str_cat.h"
#include "workers/objectives/ensemble.h"

namespace gaitforge::worker {

objectives::EnsembleSpec EnsembleOf(const v1::Robustness& r) {
  objectives::EnsembleSpec e;
  e.members = r.members();
  e.numerics.assign(r.numerics().begin(), r.numerics().end());
  for (const auto& p : r.parameters()) e.parameters.push_back({p.name(), p.lo(), p.hi(), p.log()});
  for (const auto& sample : r.samples())
    e.samples.emplace_back(sample.values().begin(), sample.values().end());
  e.start_phases = r.start_phases();
  objectives::ParseStatistic(r.statistic(), &e.statistic);  // validated with the spec
  e.quantile = r.quantile();
  e.k = r.k();
  e.seed = r.seed();
  return e;
}

objectives::EvalResult EvaluateJob(const objectives::ObjectiveRegistry& registry,
                                   const v1::Job& job, const FetchedRecordings& fetched) {
  objectives::EvalResult r;
  const objectives::Objective* obj = registry.Find(job.objective().name());
  if (!obj) {
    r.reason =
        absl::StrCat("objective '", job.objective().name(), "' is not built into this worker");
    return r;
  }
  objectives::EvalInput in;
  in.genes.assign(job.genes().begin(), job.genes().end());
  for (const auto& b : job.bounds()) {
    in.lo.push_back(b.lo());
    in.hi.push_back(b.hi());
  }
  for (const auto& [k, v] : job.objective().params()) in.params[k] = v;
  for (const auto& [k, v] : job.objective().options()) in.options[k] = v;
  in.robot = job.objective().robot();
  in.robot_descriptor = job.objective().robot_descriptor();
  for (const auto& b : job.bounds()) in.gene_names.push_back(b.name());
  std::string missing;
  for (const auto& hash : job.objective().recordings()) {
    auto it = fetched.find(hash);
    if (it == fetched.end())
      missing = absl::StrCat("recording ", hash, " is not available: not fetched");
    else if (it->second.ok())
      in.recordings.push_back(*it->second);
    else
      missing = absl::StrCat("recording ", hash, " is not available: ", it->second.status().message());
  }
  if (!missing.empty()) {
    r.reason = missing;
  } else if (in.lo.size() != in.genes.size()) {
    r.reason = absl::StrCat("job has ", in.genes.size(), " genes but ", in.lo.size(), " bounds");
  } else if (job.objective().has_robust()) {
    r = objectives::EvaluateEnsemble(*obj, in, EnsembleOf(job.objective().robust()));
  } else {
    r = objectives::EvaluateSafely(*obj, in);
  }
  return r;
}

void FillResult(v1::JobResult* out, const objectives::EvalResult& r, double eval_seconds) {
  auto* e = out->mutable_evaluation();
  e->set_valid(r.valid);
  e->set_fitness(r.fitness);
  e->set_reason(r.reason);
  for (const auto& [k, v] : r.metrics) (*e->mutable_metrics())[k] = v;
  out->set_eval_seconds(eval_seconds);
}

}  // namespace gaitforge::worker
