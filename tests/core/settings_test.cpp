#include "pf2/core/settings.h"

#include <cstdio>
#include <fstream>

#include <gtest/gtest.h>

#include "pf2/core/config_file.h"
#include "pf2/core/error.h"

namespace pf2 {
namespace {

struct Knobs {
  double voxel = 0.01;
  int levels = 3;
  bool map = true;
  std::string mode = "fast";
};

Settings declare(Knobs* k) {
  Settings s;
  s.number("map.voxel", &k->voxel, 0.002, 0.2, "metres", "voxel edge")
      .integer("odometry.levels", &k->levels, 1, 6, "levels", "pyramid levels")
      .boolean("map.build", &k->map, "fuse the map")
      .choice("run.mode", &k->mode, {"fast", "exact"}, "how to run");
  return s;
}

// The message of the pf2::Error `f` throws ("" when it does not throw).
template <typename F>
std::string errorOf(F f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Settings, SetsFieldsFromTextAndRefusesValuesOutsideTheirRange) {
  Knobs k;
  Settings s = declare(&k);
  s.set("map.voxel", "0.05");
  s.setAssignment("odometry.levels=5");
  s.set("map.build", "off");
  s.set("run.mode", "exact");
  EXPECT_DOUBLE_EQ(k.voxel, 0.05);
  EXPECT_EQ(k.levels, 5);
  EXPECT_FALSE(k.map);
  EXPECT_EQ(k.mode, "exact");
  EXPECT_EQ(errorOf([&] { s.set("map.voxel", "100"); }),
            "setting map.voxel = 100: outside its range [0.002, 0.2] metres");
  EXPECT_DOUBLE_EQ(k.voxel, 0.05);  // left as it was
  EXPECT_EQ(errorOf([&] { s.set("odometry.levels", "2.5"); }), "setting odometry.levels = 2.5: expected an integer levels");
  EXPECT_EQ(errorOf([&] { s.set("run.mode", "slow"); }), "setting run.mode = slow: expected one of fast, exact");
  EXPECT_NE(errorOf([&] { s.set("map.voxels", "1"); }).find("unknown setting 'map.voxels'"), std::string::npos);
  EXPECT_NE(errorOf([&] { s.setAssignment("map.voxel"); }).find("expected key=value"), std::string::npos);
}

TEST(Settings, ValidatesValuesSetInCodeAndRulesBetweenSettings) {
  Knobs k;
  Settings s = declare(&k);
  s.require([&k] { return k.levels >= 2 || !k.map; }, "a map needs odometry.levels >= 2");
  EXPECT_NO_THROW(s.validate());
  k.voxel = 1e-6;
  EXPECT_EQ(errorOf([&] { s.validate(); }), "setting map.voxel = 1e-06 is outside its range [0.002, 0.2] metres");
  k.voxel = 0.01;
  k.levels = 1;
  EXPECT_EQ(errorOf([&] { s.validate(); }), "settings: a map needs odometry.levels >= 2");
  // A key declared twice is a programming error.
  EXPECT_THROW(declare(&k).integer("odometry.levels", &k.levels, 1, 6, "", ""), Error);
}

TEST(Settings, ReadsAConfigFileAndNamesTheLineOfABadValueOrUnknownKey) {
  const std::string path = ::testing::TempDir() + "/pf2_settings_test.cfg";
  auto load = [&](const std::string& text) {
    std::ofstream(path) << text;
    return ConfigFile::load(path);
  };
  Knobs k;
  declare(&k).apply(load("map.voxel 0.02  # finer\nmap.build false\n"));
  EXPECT_DOUBLE_EQ(k.voxel, 0.02);
  EXPECT_FALSE(k.map);
  EXPECT_EQ(errorOf([&] { declare(&k).apply(load("map.build true\nodometry.levels 9\n")); }),
            path + ":2: setting odometry.levels = 9: outside its range [1, 6] levels");
  EXPECT_EQ(errorOf([&] { declare(&k).apply(load("map.voxel 0.02\nmap.voxle 0.03\n")); }),
            path + ":2: unknown key 'map.voxle'");
  std::remove(path.c_str());
}

TEST(Settings, ValuesReadBackAndTheTableListsDefaults) {
  Knobs k;
  Settings s = declare(&k);
  for (const std::string& key : s.keys()) {
    const std::string before = s.value(key);
    s.set(key, before);
    EXPECT_EQ(s.value(key), before) << key;
  }
  k.voxel = 0.03;  // the table keeps the defaults it was declared with
  const std::string table = s.markdown();
  EXPECT_NE(table.find("| `map.voxel` | 0.01 | metres | [0.002, 0.2] | voxel edge |"), std::string::npos);
  EXPECT_NE(table.find("| `run.mode` | fast |  | fast, exact | how to run |"), std::string::npos);
}

}  // namespace
}  // namespace pf2
