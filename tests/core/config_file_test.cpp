#include "pf2/core/config_file.h"

#include <fstream>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

std::string write(const std::string& name, const std::string& text) {
  const std::string path = testing::TempDir() + name;
  std::ofstream(path) << text;
  return path;
}

TEST(ConfigFile, ReadsTypedValuesWithFallbacks) {
  const ConfigFile config = ConfigFile::load(write(
      "pf2_ok.cfg", "# run settings\r\nsurface.voxel_size 0.02  # metres\r\n\r\n"
                    "tracker.levels 4\nfilter.temporal off\ndetector.name hog\n"));
  EXPECT_DOUBLE_EQ(config.number("surface.voxel_size", 0.01), 0.02);
  EXPECT_EQ(config.integer("tracker.levels", 3), 4);
  EXPECT_FALSE(config.boolean("filter.temporal", true));
  EXPECT_EQ(config.text("detector.name", "gt"), "hog");
  EXPECT_DOUBLE_EQ(config.number("surface.truncation", 0.04), 0.04);  // absent: fallback
  EXPECT_NO_THROW(config.checkAllUsed());
}

TEST(ConfigFile, UnknownKeyIsReportedWithItsLine) {
  const std::string path = write("pf2_typo.cfg", "surface.voxel_size 0.02\nsurface.voxle 3\n");
  const ConfigFile config = ConfigFile::load(path);
  config.number("surface.voxel_size", 0.01);
  try {
    config.checkAllUsed();
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":2:"), std::string::npos) << e.what();
  }
}

TEST(ConfigFile, BadValuesAndLinesNameTheLine) {
  const std::string path = write("pf2_bad.cfg", "a.b 1\nc.d x\n");
  const ConfigFile config = ConfigFile::load(path);
  try {
    config.number("c.d", 0);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":2: c.d"), std::string::npos) << e.what();
  }
  EXPECT_THROW(config.boolean("c.d", true), Error);
  EXPECT_THROW(ConfigFile::load(write("pf2_bad2.cfg", "a.b 1 2\n")), Error);
  EXPECT_THROW(ConfigFile::load(write("pf2_dup.cfg", "a.b 1\na.b 2\n")), Error);
  EXPECT_THROW(ConfigFile::load(testing::TempDir() + "pf2_no_such.cfg"), Error);
}

}  // namespace
}  // namespace pf2
