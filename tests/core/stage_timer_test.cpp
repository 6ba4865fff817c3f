#include "pf2/core/stage_timer.h"

#include <thread>

#include <gtest/gtest.h>

namespace pf2 {
namespace {

TEST(StageStats, MedianAndP90) {
  StageStats stats;
  for (int i = 1; i <= 11; ++i) stats.add("filter", i);  // 1..11 ms
  stats.add("track", 4.0);
  const StageSummary s = stats.summary("filter");
  EXPECT_EQ(s.count, 11);
  EXPECT_DOUBLE_EQ(s.median_ms, 6.0);
  EXPECT_DOUBLE_EQ(s.p90_ms, 10.0);
  EXPECT_DOUBLE_EQ(s.mean_ms, 6.0);
  EXPECT_DOUBLE_EQ(s.max_ms, 11.0);
  EXPECT_EQ(stats.stages(), (std::vector<std::string>{"filter", "track"}));
  EXPECT_EQ(stats.summary("unknown").count, 0);
  EXPECT_NE(stats.toJson().find("\"filter\":{\"count\":11,\"median_ms\":6.0000"), std::string::npos);
}

TEST(StageStats, ScopedTimerMeasuresSleep) {
  StageStats stats;
  {
    ScopedStageTimer timer(&stats, "sleep");
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(stats.summary("sleep").count, 1);
  EXPECT_GE(stats.summary("sleep").median_ms, 19.0);
}

TEST(StageStats, ConcurrentAddsAreAllCounted) {
  StageStats stats;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&stats] {
      for (int i = 0; i < 1000; ++i) stats.add("stage", 1.0);
    });
  }
  for (auto& t : threads) t.join();
  EXPECT_EQ(stats.summary("stage").count, 4000);
}

TEST(Percentile, InterpolatesBetweenOrderStatistics) {
  EXPECT_DOUBLE_EQ(percentile({}, 50), 0.0);
  EXPECT_DOUBLE_EQ(percentile({3.0, 1.0}, 50), 2.0);
  EXPECT_DOUBLE_EQ(percentile({5.0, 1.0, 3.0, 2.0, 4.0}, 25), 2.0);
  EXPECT_DOUBLE_EQ(percentile({5.0, 1.0, 3.0}, 100), 5.0);
}

}  // namespace
}  // namespace pf2
