#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/slam/slam_options.h"

namespace pf2 {
namespace {

TEST(SlamSettings, DefaultsAreWithinTheirRangesAndEveryKeyReadsBack) {
  SlamOptions options;
  Settings settings = slamSettings(&options);
  EXPECT_NO_THROW(settings.validate());
  ASSERT_GT(settings.keys().size(), 60u);
  for (const std::string& key : settings.keys()) {
    const std::string before = settings.value(key);
    settings.set(key, before);
    EXPECT_EQ(settings.value(key), before) << key;
  }
  // Each key reaches its field: a changed value shows in the options.
  settings.set("map.voxel_size", "0.02");
  settings.set("tracker.local_edges", "5");
  settings.set("filter.use_mask", "false");
  settings.set("humans.association", "paper");
  EXPECT_DOUBLE_EQ(options.mapper.tsdf.voxel_size, 0.02);
  EXPECT_EQ(options.tracker.backend.local_edges, 5);
  EXPECT_FALSE(options.filter.use_mask);
  EXPECT_EQ(toString(options.humans.association), std::string("paper"));
}

// Every setting refuses a value beyond each end of its range (or outside its list) with its key
// named, and keeps its value.
TEST(SlamSettings, EveryOutOfRangeValueIsRefusedWithItsKeyNamed) {
  SlamOptions options;
  Settings settings = slamSettings(&options);
  for (const std::string& key : settings.keys()) {
    const std::string allowed = settings.allowed(key);
    // Whole numbers beyond integer ranges, so an integer setting fails on its range, not its type.
    std::vector<std::string> bad{"not-a-value"};
    double lo = 0, hi = 0;
    if (std::sscanf(allowed.c_str(), "[%lf, %lf]", &lo, &hi) == 2) {
      char below[64], above[64];
      std::snprintf(below, sizeof(below), "%.10g", std::floor(lo - 1.0 - std::fabs(lo)));
      std::snprintf(above, sizeof(above), "%.10g", std::ceil(hi + 1.0 + std::fabs(hi)));
      bad = {below, above};
    }
    const std::string before = settings.value(key);
    for (const std::string& value : bad) {
      try {
        settings.set(key, value);
        ADD_FAILURE() << key << " accepted " << value << " (allowed " << allowed << ")";
      } catch (const Error& e) {
        const std::string message = e.what();
        EXPECT_NE(message.find("setting " + key + " = " + value), std::string::npos) << message;
        if (bad.size() == 2) {
          EXPECT_NE(message.find("outside its range " + allowed), std::string::npos) << message;
        }
      }
      EXPECT_EQ(settings.value(key), before) << key;
    }
  }
}

}  // namespace
}  // namespace pf2
