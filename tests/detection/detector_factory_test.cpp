#include "pf2/detection/detector_factory.h"

#include <algorithm>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "test_folder.h"

namespace pf2 {
namespace {

TEST(DetectorFactory, CreatesByNameAndListsNames) {
  const auto names = humanDetectorNames();
  for (const char* n : {"file", "gt", "hog", "yolo"}) {
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  }
  DetectorOptions o;
  EXPECT_EQ(createHumanDetector("hog", o)->name(), "hog");
  const std::string dir = freshTestFolder("pf2_factory");
  writeText(dir + "/boxes.txt", "1.0 1 2 3 4 0.9\n");
  o.file.path = dir + "/boxes.txt";
  EXPECT_EQ(createHumanDetector("file", o)->name(), "file");
  try {
    createHumanDetector("nope", o);
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("hog"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pf2
