// The worker's robot descriptors by content hash: fetched once, checked, put back into jobs.
#include "workers/protocol/descriptor_cache.h"

#include <gtest/gtest.h>

#include "services/recording/recording.h"

namespace gaitforge::worker {
namespace {

TEST(DescriptorCache, FetchesOnceChecksTheHashAndFillsTheJobs) {
  const std::string text = "format: gaitforge.robot.v1\nname: r\n";
  const std::string hash = recording::ContentHash(text, "");
  std::string served = "tampered";
  int calls = 0;
  DescriptorCache cache([&](const std::string& h) -> absl::StatusOr<std::string> {
    ++calls;
    if (h != hash) return absl::NotFoundError("no such descriptor");
    return served;
  });
  // Bytes that do not hash to the name are refused and not kept.
  EXPECT_EQ(cache.Get(hash).status().code(), absl::StatusCode::kDataLoss);
  served = text;
  v1::LeaseResponse lease;
  for (int i = 0; i < 3; ++i) lease.add_jobs()->mutable_objective()->set_robot_descriptor_hash(hash);
  lease.add_jobs()->mutable_objective()->set_name("analytic.sphere");  // names none
  ASSERT_TRUE(cache.Fill(lease).ok());
  for (int i = 0; i < 3; ++i) EXPECT_EQ(lease.jobs(i).objective().robot_descriptor(), text);
  EXPECT_TRUE(lease.jobs(3).objective().robot_descriptor().empty());
  EXPECT_EQ(calls, 2);  // the refused fetch, then one for three jobs
  EXPECT_EQ(cache.fetches(), 2);
  // An unknown hash: the fetch's error, first error wins.
  v1::LeaseResponse other;
  other.add_jobs()->mutable_objective()->set_robot_descriptor_hash("beef");
  EXPECT_EQ(cache.Fill(other).code(), absl::StatusCode::kNotFound);
}

}  // namespace
}  // namespace gaitforge::worker
