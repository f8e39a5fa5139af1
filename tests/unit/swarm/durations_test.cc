// bench/swarm's evaluation times: parsed from the command line, a pure function of the job.
#include "bench/swarm/durations.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "bench/swarm/event_loop.h"
#include "bench/swarm/swarm_stats.h"

namespace gaitforge::swarm {
namespace {

v1::JobKey Key(int g, int m) {
  v1::JobKey k;
  k.set_study_id("s-1");
  k.set_generation(g);
  k.set_member(m);
  return k;
}

TEST(Durations, Parse) {
  EXPECT_TRUE(Durations::Parse("constant:0.5").ok());
  EXPECT_TRUE(Durations::Parse("lognormal:0.5:1").ok());
  for (const char* bad : {"", "constant", "constant:x", "constant:-1", "lognormal:0:1",
                          "lognormal:1", "uniform:1:2", "lognormal:1:9"})
    EXPECT_FALSE(Durations::Parse(bad).ok()) << bad;
}

TEST(Durations, ConstantAndDeterministicLognormal) {
  EXPECT_EQ(Durations::Parse("constant:0.05")->Draw(Key(0, 0)), 0.05);
  const Durations d = *Durations::Parse("lognormal:0.5:1");
  std::vector<double> xs;
  for (int m = 0; m < 20000; ++m) {
    xs.push_back(d.Draw(Key(1, m)));
    ASSERT_EQ(xs.back(), d.Draw(Key(1, m)));
  }
  double sum = 0;
  for (double x : xs) sum += x;
  EXPECT_NEAR(sum / xs.size(), 0.5, 0.05);
  std::vector<double> sorted = xs;
  const double p99 = Quantile(sorted, 0.99), p50 = Quantile(sorted, 0.5);
  EXPECT_GT(p99 / p50, 5);  // a heavy tail
}

TEST(EventLoop, RunsTasksInTimeOrder) {
  EventLoop loop;
  std::vector<int> order;
  loop.After(30, [&] { order.push_back(3); });
  loop.After(10, [&] { order.push_back(1); });
  loop.Post([&] { order.push_back(0); });
  loop.After(20, [&] { order.push_back(2); });
  loop.After(40, [&] { loop.Stop(); });
  loop.Run();
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3}));
}

TEST(SwarmStats, BusyTimeIsClippedToTheWindow) {
  SwarmStats st;
  const auto t0 = Clock::now();
  using ms = std::chrono::milliseconds;
  st.busy.emplace_back(t0, t0 + ms(1000));
  st.busy.emplace_back(t0 + ms(500), t0 + ms(2000));
  EXPECT_NEAR(SwarmStats::BusySeconds(st.busy, t0 + ms(500), t0 + ms(1500)), 1.5, 1e-9);
  st.last_report[{"s", 0}] = t0;
  st.first_lease[{"s", 1}] = t0 + ms(7);
  ASSERT_EQ(st.TurnaroundsMs().size(), 1u);
  EXPECT_NEAR(st.TurnaroundsMs()[0], 7, 1e-9);
}

}  // namespace
}  // namespace gaitforge::swarm
