// A leased job evaluated (workers/protocol/job_eval.h): problems become invalid results with
// a reason, and the fitness is the objective's own.
#include "workers/protocol/job_eval.h"

#include <gtest/gtest.h>

namespace gaitforge::worker {
namespace {

v1::Job SphereJob(int genes, int bounds) {
  v1::Job job;
  job.mutable_objective()->set_name("analytic.sphere");
  for (int i = 0; i < genes; ++i) job.add_genes(0.25);
  for (int i = 0; i < bounds; ++i) {
    auto* b = job.add_bounds();
    b->set_lo(0);
    b->set_hi(1);
  }
  return job;
}

TEST(JobEval, SameJobSameBits) {
  const auto reg = objectives::DefaultRegistry();
  const auto a = EvaluateJob(reg, SphereJob(3, 3), {});
  const auto b = EvaluateJob(reg, SphereJob(3, 3), {});
  EXPECT_TRUE(a.valid) << a.reason;
  EXPECT_EQ(a.fitness, b.fitness);
}

TEST(JobEval, ProblemsAreInvalidResults) {
  const auto reg = objectives::DefaultRegistry();
  v1::Job unknown = SphereJob(1, 1);
  unknown.mutable_objective()->set_name("no.such");
  EXPECT_EQ(EvaluateJob(reg, unknown, {}).reason, "objective 'no.such' is not built into this worker");
  EXPECT_EQ(EvaluateJob(reg, SphereJob(2, 1), {}).reason, "job has 2 genes but 1 bounds");
  v1::Job rec = SphereJob(1, 1);
  rec.mutable_objective()->add_recordings("abc");
  FetchedRecordings fetched;
  fetched.emplace("abc", absl::NotFoundError("gone"));
  EXPECT_EQ(EvaluateJob(reg, rec, fetched).reason, "recording abc is not available: gone");
  EXPECT_FALSE(EvaluateJob(reg, rec, {}).valid);
}

TEST(JobEval, FillResult) {
  objectives::EvalResult r;
  r.valid = true;
  r.fitness = -1.5;
  r.metrics["x"] = 2;
  v1::JobResult out;
  FillResult(&out, r, 0.25);
  EXPECT_TRUE(out.evaluation().valid());
  EXPECT_EQ(out.evaluation().fitness(), -1.5);
  EXPECT_EQ(out.evaluation().metrics().at("x"), 2);
  EXPECT_EQ(out.eval_seconds(), 0.25);
}

}  // namespace
}  // namespace gaitforge::worker
