#include "services/queue/job_queue.h"

#include <gtest/gtest.h>

namespace gaitforge::queue {
namespace {

const auto kAll = [](const JobKey&) { return true; };

class JobQueueTest : public ::testing::Test {
 protected:
  core::ManualClock clock_;
  JobQueue q_{clock_, QueueOptions{1000, 3, 500}, 7};
  void AddJobs(int n) {
    for (int m = 0; m < n; ++m) q_.Add(JobKey{"s", 0, m});
  }
};

TEST_F(JobQueueTest, LeasesOldestFirstUpToMax) {
  AddJobs(5);
  auto l = q_.LeaseJobs("w1", 3, kAll);
  ASSERT_EQ(l.size(), 3u);
  EXPECT_EQ(l[0].key.member, 0);
  EXPECT_EQ(l[2].key.member, 2);
  EXPECT_EQ(q_.pending(), 2u);
  EXPECT_EQ(q_.in_flight(), 3u);
}

TEST_F(JobQueueTest, ExpiredLeaseReturnsJobToTheQueue) {
  AddJobs(1);
  auto l = q_.LeaseJobs("w1", 1, kAll);
  clock_.Advance(400);
  EXPECT_EQ(q_.LeaseAgeMs(l[0].lease_id), 400);
  EXPECT_EQ(q_.LeaseAgeMs(12345), -1);
  clock_.Advance(599);
  EXPECT_TRUE(q_.ExpireLeases().expired.empty());
  EXPECT_EQ(q_.pending(), 0u);
  clock_.Advance(2);
  q_.ExpireLeases();
  EXPECT_EQ(q_.pending(), 1u);
  EXPECT_EQ(q_.counters().expired, 1);
  auto again = q_.LeaseJobs("w2", 1, kAll);
  ASSERT_EQ(again.size(), 1u);
  EXPECT_NE(again[0].lease_id, l[0].lease_id);
}

TEST_F(JobQueueTest, HeartbeatRenewsEveryLeaseOfTheWorker) {
  AddJobs(3);
  q_.LeaseJobs("w1", 2, kAll);
  q_.LeaseJobs("w2", 1, kAll);
  clock_.Advance(800);
  EXPECT_EQ(q_.Heartbeat("w1"), 2);
  clock_.Advance(800);
  q_.ExpireLeases();
  EXPECT_EQ(q_.pending(), 1u);  // only w2's job came back
  EXPECT_EQ(q_.in_flight(), 2u);
}

TEST_F(JobQueueTest, CompletionIsIdempotentAndLateResultsOfTheLeaseAreAccepted) {
  AddJobs(1);
  auto l1 = q_.LeaseJobs("w1", 1, kAll);
  clock_.Advance(1500);
  q_.ExpireLeases();
  auto l2 = q_.LeaseJobs("w2", 1, kAll);
  // w1's lease expired, but the job is open: its late result may complete it.
  EXPECT_EQ(q_.Check("w1", l1[0].key, l1[0].lease_id), ReportCheck::kOpen);
  EXPECT_TRUE(q_.Complete(l1[0].key));
  EXPECT_EQ(q_.Check("w2", l2[0].key, l2[0].lease_id), ReportCheck::kDone);
  EXPECT_FALSE(q_.Complete(l2[0].key));
}

TEST_F(JobQueueTest, AWorkerCannotCompleteAJobItWasNeverLeased) {
  AddJobs(2);
  auto l = q_.LeaseJobs("w1", 1, kAll);
  EXPECT_EQ(q_.Check("w2", JobKey{"s", 0, 1}, 0), ReportCheck::kNotHeld);
  EXPECT_EQ(q_.Check("w2", JobKey{"s", 0, 1}, l[0].lease_id), ReportCheck::kNotHeld);
  // Another worker presenting w1's lease id does not hold the job either.
  EXPECT_EQ(q_.Check("w2", l[0].key, l[0].lease_id), ReportCheck::kNotHeld);
  EXPECT_EQ(q_.Check("w1", l[0].key, l[0].lease_id), ReportCheck::kOpen);
  EXPECT_EQ(q_.Check("w2", JobKey{"s", 0, 9}, 1), ReportCheck::kUnknown);
  // A lease id from another coordinator epoch (before a restart) is honoured.
  const uint64_t old_epoch = (uint64_t{8} << 32) | 5;
  EXPECT_EQ(q_.Check("w2", JobKey{"s", 0, 1}, old_epoch), ReportCheck::kOpen);
}

TEST_F(JobQueueTest, AJobIsPoisonedAfterMaxAttempts) {
  AddJobs(1);
  for (int attempt = 0; attempt < 3; ++attempt) {
    ASSERT_EQ(q_.LeaseJobs("w", 1, kAll).size(), 1u) << attempt;
    clock_.Advance(1001);
    auto expiry = q_.ExpireLeases();
    EXPECT_EQ(expiry.expired.size(), 1u);
    EXPECT_EQ(expiry.poisoned.size(), attempt == 2 ? 1u : 0u);
  }
  EXPECT_EQ(q_.counters().poisoned, 1);
  EXPECT_TRUE(q_.LeaseJobs("w", 1, kAll).empty());
  EXPECT_EQ(q_.Check("w", JobKey{"s", 0, 0}, 0), ReportCheck::kDone);
}

TEST_F(JobQueueTest, BackupCopiesGoToOtherWorkersOnlyWhenTheQueueIsEmpty) {
  AddJobs(2);
  q_.LeaseJobs("w1", 2, kAll);
  EXPECT_TRUE(q_.LeaseJobs("w2", 5, kAll).empty());  // not old enough yet
  clock_.Advance(600);
  EXPECT_TRUE(q_.LeaseJobs("w1", 5, kAll).empty());  // never to the holder
  auto backups = q_.LeaseJobs("w2", 1, kAll);
  ASSERT_EQ(backups.size(), 1u);
  EXPECT_TRUE(backups[0].backup);
  EXPECT_EQ(q_.counters().backups, 1);
  // First result wins.
  EXPECT_TRUE(q_.Complete(backups[0].key));
  EXPECT_EQ(q_.Check("w1", backups[0].key, 0), ReportCheck::kDone);
}

TEST_F(JobQueueTest, AcceptFilterAndRemoval) {
  AddJobs(3);
  q_.Add(JobKey{"t", 0, 0});
  auto l = q_.LeaseJobs("w", 10, [](const JobKey& k) { return k.study_id == "t"; });
  ASSERT_EQ(l.size(), 1u);
  q_.RemoveStudy("s");
  EXPECT_EQ(q_.pending(), 0u);
  q_.RemoveGeneration("t", 0);
  EXPECT_FALSE(q_.HasJob(JobKey{"t", 0, 0}));
}

// The counts and indexes that keep a thousand workers' calls cheap (issue 30) agree with
// the jobs' states through every transition.
TEST_F(JobQueueTest, CountsFollowEveryTransition) {
  AddJobs(4);
  EXPECT_EQ(q_.pending(), 4u);
  auto a = q_.LeaseJobs("w1", 2, kAll);
  auto b = q_.LeaseJobs("w2", 1, kAll);
  EXPECT_EQ(q_.pending(), 1u);
  EXPECT_EQ(q_.in_flight(), 3u);
  q_.Complete(a[0].key);
  EXPECT_EQ(q_.in_flight(), 2u);
  q_.Complete(JobKey{"s", 0, 3});  // a pending job completed by a late result
  EXPECT_EQ(q_.pending(), 0u);
  clock_.Advance(1001);
  q_.ExpireLeases();  // a[1] and b[0] go back
  EXPECT_EQ(q_.pending(), 2u);
  EXPECT_EQ(q_.in_flight(), 0u);
  q_.LeaseJobs("w3", 1, kAll);
  q_.RemoveStudy("s");
  EXPECT_EQ(q_.pending(), 0u);
  EXPECT_EQ(q_.in_flight(), 0u);
}

TEST_F(JobQueueTest, HeartbeatRenewsOnlyTheCallersLeases) {
  AddJobs(3);
  q_.LeaseJobs("w1", 2, kAll);
  auto other = q_.LeaseJobs("w2", 1, kAll);
  clock_.Advance(800);
  EXPECT_EQ(q_.Heartbeat("w1"), 2);
  EXPECT_EQ(q_.Heartbeat("nobody"), 0);
  clock_.Advance(300);
  const Expiry e = q_.ExpireLeases();
  ASSERT_EQ(e.expired.size(), 1u);
  EXPECT_EQ(e.expired[0], other[0].key);
  EXPECT_EQ(q_.Heartbeat("w2"), 0);  // its lease is gone
}

TEST_F(JobQueueTest, BackupsGoToTheOldestStragglersOnce) {
  AddJobs(3);
  q_.LeaseJobs("w1", 1, kAll);
  clock_.Advance(100);
  q_.LeaseJobs("w2", 2, kAll);
  clock_.Advance(450);  // only w1's job is older than 500 ms
  auto b = q_.LeaseJobs("w3", 5, kAll);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_TRUE(b[0].backup);
  EXPECT_EQ(b[0].key.member, 0);
  clock_.Advance(100);
  auto c = q_.LeaseJobs("w2", 5, kAll);  // w2's own jobs are not backed up for it
  EXPECT_TRUE(c.empty());
  auto d = q_.LeaseJobs("w4", 5, kAll);
  EXPECT_EQ(d.size(), 2u);
  EXPECT_TRUE(q_.LeaseJobs("w5", 5, kAll).empty());  // one backup per job
}

// A job is a straggler against what its batch should take (issue 30): the last of ten
// 100 ms jobs is not late at 1.5 s, while a single job out that long is.
TEST_F(JobQueueTest, AStragglerIsLateForItsBatchNotForAFixedTime) {
  q_.set_job_ms(100);
  AddJobs(11);
  auto ten = q_.LeaseJobs("w1", 10, kAll);  // a straggler after 2 x 10 x 100 ms
  auto one = q_.LeaseJobs("w2", 1, kAll);   // after 500 ms (backup_after_ms)
  ASSERT_EQ(ten.size(), 10u);
  clock_.Advance(1500);
  auto b = q_.LeaseJobs("w3", 20, kAll);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_EQ(b[0].key, one[0].key);
  clock_.Advance(600);
  EXPECT_EQ(q_.LeaseJobs("w3", 20, kAll).size(), 10u);
}

TEST_F(JobQueueTest, RemoveGenerationForgetsItsLeaseIdsButRemoveStudyKeepsThem) {
  q_.Add(JobKey{"s", 0, 0});
  q_.Add(JobKey{"t", 0, 0});
  auto s0 = q_.LeaseJobs("w1", 1, kAll);
  auto t0 = q_.LeaseJobs("w1", 1, kAll);
  q_.Complete(s0[0].key);
  q_.RemoveGeneration("s", 0);
  EXPECT_EQ(q_.LeaseAgeMs(s0[0].lease_id), -1);
  q_.RemoveStudy("t");
  q_.Add(JobKey{"t", 0, 0});  // resumed
  EXPECT_EQ(q_.Check("w1", JobKey{"t", 0, 0}, t0[0].lease_id), ReportCheck::kOpen);
}

}  // namespace
}  // namespace gaitforge::queue
