#include "tests/integration/study_driver.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "workers/protocol/job_eval.h"
#include "workers/protocol/wire.h"

namespace gaitforge::testing {

int Drive(coordinator::Coordinator& c, const DriveOptions& o) {
  static const auto registry = objectives::DefaultRegistry();
  int reports = 0;
  for (;;) {
    if (o.max_reports >= 0 && reports >= o.max_reports) return reports;
    v1::LeaseRequest lreq;
    lreq.mutable_worker()->set_worker_id(o.worker_id);
    lreq.set_max_jobs(o.batch);
    auto lease = c.Lease(lreq);
    EXPECT_TRUE(lease.ok()) << lease.status();
    if (!lease.ok() || lease->jobs_size() == 0) return reports;
    EXPECT_TRUE(worker::ExpandLease(*lease).ok());
    v1::ReportRequest rep;
    rep.mutable_worker()->set_worker_id(o.worker_id);
    std::vector<int> idx(lease->jobs_size());
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<int>(i);
    if (o.reverse) std::reverse(idx.begin(), idx.end());
    for (int i : idx) {
      const auto& job = lease->jobs(i);
      auto* res = rep.add_results();
      *res->mutable_key() = job.key();
      res->set_lease_id(job.lease_id());
      worker::FillResult(res, worker::EvaluateJob(registry, job, {}), 0);
    }
    auto ok = c.Report(rep);
    EXPECT_TRUE(ok.ok()) << ok.status();
    ++reports;
  }
}

StudyDump Dump(coordinator::Coordinator& c, const std::string& id) {
  StudyDump d;
  auto hist = c.History(id);
  EXPECT_TRUE(hist.ok()) << hist.status();
  d.generations = hist->generations_size();
  for (int g = 0; g < d.generations; ++g) {
    auto inds = c.Individuals(id, g);
    EXPECT_TRUE(inds.ok());
    for (const auto& i : inds->individuals()) {
      d.genes.emplace_back(i.genes().begin(), i.genes().end());
      d.fitness.push_back(i.evaluation().fitness());
    }
    auto hof = c.HallOfFame(id, g);
    EXPECT_TRUE(hof.ok());
    for (const auto& e : hof->entries()) {
      d.hof_genes.emplace_back(e.individual().genes().begin(), e.individual().genes().end());
      d.hof_fitness.push_back(e.individual().evaluation().fitness());
    }
  }
  return d;
}

v1::StudySpec SmallSpec(uint64_t seed, int population, int generations) {
  v1::StudySpec s;
  s.set_name("it");
  s.set_seed(seed);
  s.set_population(population);
  s.set_generations(generations);
  s.mutable_objective()->set_name("analytic.rastrigin");
  return s;
}

}  // namespace gaitforge::testing
