// The worker's wire protocol as pure functions (workers/protocol/wire.h): what both
// gaitforge-worker and the emulated workers of bench/swarm send and how they retry.
#include "workers/protocol/wire.h"

#include <gtest/gtest.h>

namespace gaitforge::worker {
namespace {

TEST(Wire, RetryableCodesAreTheDocumentedOnes) {
  for (auto c : {grpc::StatusCode::UNAVAILABLE, grpc::StatusCode::DEADLINE_EXCEEDED,
                 grpc::StatusCode::RESOURCE_EXHAUSTED, grpc::StatusCode::ABORTED,
                 grpc::StatusCode::INTERNAL, grpc::StatusCode::UNKNOWN})
    EXPECT_TRUE(Retryable(grpc::Status(c, ""))) << c;
  for (auto c : {grpc::StatusCode::UNAUTHENTICATED, grpc::StatusCode::PERMISSION_DENIED,
                 grpc::StatusCode::FAILED_PRECONDITION, grpc::StatusCode::INVALID_ARGUMENT,
                 grpc::StatusCode::NOT_FOUND, grpc::StatusCode::CANCELLED})
    EXPECT_FALSE(Retryable(grpc::Status(c, ""))) << c;
}

TEST(Wire, ReportFate) {
  EXPECT_EQ(ClassifyReport(grpc::Status::OK), ReportFate::kLanded);
  EXPECT_EQ(ClassifyReport(grpc::Status(grpc::StatusCode::UNAVAILABLE, "")), ReportFate::kRetry);
  // Too large: it would fail again.
  EXPECT_EQ(ClassifyReport(grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED, "")),
            ReportFate::kDrop);
  EXPECT_EQ(ClassifyReport(grpc::Status(grpc::StatusCode::FAILED_PRECONDITION, "")),
            ReportFate::kDrop);
}

TEST(Wire, BackoffDoublesWithJitterUpToFiveSeconds) {
  Backoff b(1);
  int step = 100;
  for (int i = 0; i < 10; ++i) {
    const int d = b.NextDelayMs();
    EXPECT_GE(d, step / 2);
    EXPECT_LE(d, step);
    step = std::min(step * 2, 5000);
  }
  b.Reset();
  EXPECT_LE(b.NextDelayMs(), 100);
}

TEST(Wire, BatchSizingAsksForUpToFiveSeconds) {
  EXPECT_EQ(WantJobs(1, 0, 256), 4);  // unknown: 4 per thread
  EXPECT_EQ(WantJobs(2, 0, 256), 8);
  EXPECT_EQ(WantJobs(1, 0.05, 256), 100);  // 2 s with 2.5x headroom
  EXPECT_EQ(WantJobs(4, 0.5, 256), 40);
  EXPECT_EQ(WantJobs(1, 5.0, 256), 1);
  EXPECT_EQ(WantJobs(1, 1e-9, 256), 256);   // capped by --max-batch
  EXPECT_EQ(WantJobs(8, 1e-9, 4096), 1024); // and by the protocol's 1024
  EXPECT_DOUBLE_EQ(UpdateMeanEval(0, 1.0, 2, 4), 0.5);
  EXPECT_DOUBLE_EQ(UpdateMeanEval(1.0, 2.0, 1, 1), 0.7 + 0.6);
}

TEST(Wire, Messages) {
  const v1::WorkerInfo info = MakeWorkerInfo("w1", 3, "build-x", {"analytic.sphere"});
  EXPECT_EQ(info.worker_id(), "w1");
  EXPECT_EQ(info.threads(), 3);
  EXPECT_EQ(info.sim_build(), "build-x");
  ASSERT_EQ(info.objectives_size(), 1);
  EXPECT_FALSE(MakeWorkerInfo("", 1, "", {}).worker_id().empty());
  const v1::LeaseRequest lease = MakeLeaseRequest(info, 5000);
  EXPECT_EQ(lease.max_jobs(), 1024);
  EXPECT_EQ(lease.wait_ms(), kLeaseWaitMs);
  EXPECT_EQ(lease.worker().worker_id(), "w1");
  EXPECT_EQ(MakeHeartbeatRequest(info).worker().worker_id(), "w1");
  EXPECT_EQ(HeartbeatIntervalMs(300), 200);
  EXPECT_EQ(HeartbeatIntervalMs(30000), 10000);
}

TEST(Wire, ReportHasOneResultPerJobInLeaseOrder) {
  v1::LeaseResponse lease;
  for (int m : {3, 1}) {
    v1::Job* j = lease.add_jobs();
    j->mutable_key()->set_study_id("s");
    j->mutable_key()->set_member(m);
    j->set_lease_id(100 + m);
  }
  const v1::ReportRequest r = StartReport(MakeWorkerInfo("w", 1, "", {}), lease);
  ASSERT_EQ(r.results_size(), 2);
  EXPECT_EQ(r.results(0).key().member(), 3);
  EXPECT_EQ(r.results(0).lease_id(), 103u);
  EXPECT_EQ(r.results(1).lease_id(), 101u);
  EXPECT_EQ(r.worker().worker_id(), "w");
}


TEST(Wire, ExpandLeaseCopiesEachStudysContextIntoItsJobs) {
  v1::LeaseResponse lease;
  for (const char* id : {"a", "b"}) {
    v1::StudyContext* c = lease.add_studies();
    c->set_study_id(id);
    c->mutable_objective()->set_name(std::string("obj-") + id);
    c->add_bounds()->set_name(std::string("gene-") + id);
  }
  for (const char* id : {"b", "a", "b"}) lease.add_jobs()->mutable_key()->set_study_id(id);
  ASSERT_TRUE(ExpandLease(lease).ok());
  EXPECT_EQ(lease.jobs(0).objective().name(), "obj-b");
  EXPECT_EQ(lease.jobs(1).objective().name(), "obj-a");
  ASSERT_EQ(lease.jobs(2).bounds_size(), 1);
  EXPECT_EQ(lease.jobs(2).bounds(0).name(), "gene-b");

  v1::LeaseResponse orphan;  // a job whose study sent no context: refused, named
  orphan.add_jobs()->mutable_key()->set_study_id("c");
  const absl::Status s = ExpandLease(orphan);
  EXPECT_EQ(s.code(), absl::StatusCode::kDataLoss);
  EXPECT_NE(s.message().find("study 'c'"), std::string::npos) << s.message();
}

}  // namespace
}  // namespace gaitforge::worker
