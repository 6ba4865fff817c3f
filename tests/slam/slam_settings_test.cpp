#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/core/settings.h"
#include "pf2/detection/box_degradation.h"
#include "pf2/io/tum_sequence_settings.h"
#include "pf2/slam/slam_options.h"
#include "pf2/synth/synth_settings.h"

namespace pf2 {
namespace {

// Defaults pass validation and every key reads back what it was set to.
void expectEveryKeyRoundTrips(Settings& settings) {
  EXPECT_NO_THROW(settings.validate());
  for (const std::string& key : settings.keys()) {
    const std::string before = settings.value(key);
    settings.set(key, before);
    EXPECT_EQ(settings.value(key), before) << key;
  }
}

// Every setting refuses a value beyond each end of its range (or outside its list) with its key
// named, and keeps its value.
void expectOutOfRangeValuesRefused(Settings& settings) {
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
    // File names accept any text.
    if (allowed == "a file name") continue;
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

TEST(SlamSettings, DefaultsAreWithinTheirRangesAndEveryKeyReadsBack) {
  SlamOptions options;
  Settings settings = slamSettings(&options);
  ASSERT_GT(settings.keys().size(), 60u);
  expectEveryKeyRoundTrips(settings);
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

TEST(SlamSettings, EveryOutOfRangeValueIsRefusedWithItsKeyNamed) {
  SlamOptions options;
  Settings settings = slamSettings(&options);
  expectOutOfRangeValuesRefused(settings);
}

// The other apps' settings lists follow the same rules.
TEST(AppSettings, SyntheticInputAndDegradationSettingsRoundTripAndRefuseOutOfRange) {
  SyntheticSequence::Options synth;
  TumSequence::Options input;
  BoxDegradation degradation;
  Settings settings;
  declareSynthSettings(&synth, &settings);
  declareTumSequenceSettings(&input, &settings);
  declareBoxDegradationSettings("boxes.", &degradation, &settings);
  ASSERT_EQ(settings.keys().size(), 17u);
  expectEveryKeyRoundTrips(settings);
  expectOutOfRangeValuesRefused(settings);
  settings.set("synth.camera", "loop");
  settings.set("synth.seed", "2147483647");
  settings.set("input.depth_scale", "1000");
  settings.set("boxes.shift", "4");
  EXPECT_EQ(synth.camera, CameraMotion::kLoop);
  EXPECT_EQ(synth.seed, 2147483647u);
  EXPECT_DOUBLE_EQ(input.depth_scale, 1000.0);
  EXPECT_DOUBLE_EQ(degradation.shift, 4.0);
}

// Every preset sets only declared settings to allowed values, and "offline" gives the learned
// detector its matte and crop masks and the map what the rules beside the masks took; an unknown
// name is refused with the names there are.
TEST(SlamPresets, SetDeclaredSettingsAndUnknownNamesAreRefused) {
  ASSERT_FALSE(slamPresets().empty());
  for (const SlamPreset& preset : slamPresets()) {
    SlamOptions options;
    Settings settings = slamSettings(&options);
    EXPECT_NO_THROW(applySlamPreset(preset.name, &settings)) << preset.name;
    EXPECT_NO_THROW(settings.validate()) << preset.name;
    EXPECT_FALSE(preset.meaning.empty()) << preset.name;
  }
  SlamOptions options;
  Settings settings = slamSettings(&options);
  applySlamPreset("offline", &settings);
  EXPECT_EQ(options.learned_segmenter, "rvm");
  EXPECT_TRUE(options.learned_crop_masks);
  EXPECT_TRUE(options.filter.outside_masks_tracker_only);
  EXPECT_FALSE(SlamOptions().filter.outside_masks_tracker_only);
  try {
    applySlamPreset("fast", &settings);
    ADD_FAILURE() << "no error for an unknown preset";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("'fast'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("offline"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pf2
