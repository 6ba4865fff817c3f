#include "pf2/detection/gt_detector.h"

#include <sys/stat.h>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "pf2/core/error.h"
#include "test_folder.h"

namespace pf2 {
namespace {

// gt/ folder of two frames: person 1 and 2 in frame 10.000000, person 2 only in 10.033333.
std::string makeGt(const std::string& name, const std::string& boxes) {
  const std::string dir = freshTestFolder(name);
  ::mkdir((dir + "/masks").c_str(), 0755);
  writeText(dir + "/boxes.txt", boxes);
  cv::Mat ids = cv::Mat::zeros(30, 40, CV_16U);
  ids(cv::Rect(2, 3, 10, 15)).setTo(1);
  ids(cv::Rect(20, 5, 5, 20)).setTo(2);
  cv::imwrite(dir + "/masks/10.000000.png", ids);
  ids(cv::Rect(2, 3, 10, 15)).setTo(0);
  cv::imwrite(dir + "/masks/10.033333.png", ids);
  return dir;
}

const char* kBoxes =
    "# timestamp id x_ul y_ul x_lr y_lr visible_fraction\n"
    "10.000000 1 2 3 11 17 0.9\r\n"
    "10.000000 2 20 5 24 24 0.3\n"
    "\n"
    "10.033333 2 20 5 24 24 1.0\n";

Frame frameAt(double t) {
  Frame f;
  f.timestamp = t;
  f.depth = cv::Mat::zeros(30, 40, CV_32F);
  f.rgb = cv::Mat::zeros(30, 40, CV_8UC3);
  return f;
}

TEST(GtDetector, ReadsBoxesAndMasksByNearestStamp) {
  GtDetector::Options o;
  o.gt_folder = makeGt("pf2_gt_ok", kBoxes);
  o.provide_mask = true;
  GtDetector detector(o);
  EXPECT_EQ(detector.name(), "gt");
  const Detections d = detector.detect(frameAt(10.004));
  ASSERT_EQ(d.people.size(), 2u);
  EXPECT_EQ(d.people[0].box.x_ul, 2.f);
  EXPECT_EQ(d.people[0].box.y_lr, 18.f);  // inclusive 17 in the file
  EXPECT_EQ(d.people[0].box.width(), 10.f);
  EXPECT_EQ(d.people[0].score, 1.f);
  ASSERT_FALSE(d.people[0].mask.empty());
  EXPECT_EQ(cv::countNonZero(d.people[0].mask), 150);
  EXPECT_EQ(cv::countNonZero(d.people[1].mask), 100);
  EXPECT_EQ(d.people[1].mask.at<uint8_t>(5, 20), 255);
  EXPECT_EQ(detector.detect(frameAt(10.03)).people.size(), 1u);
  EXPECT_TRUE(detector.detect(frameAt(10.1)).people.empty());  // beyond 0.02 s
  o.min_visible_fraction = 0.5;
  GtDetector visible(o);
  EXPECT_EQ(visible.detect(frameAt(10.0)).people.size(), 1u);
}

TEST(GtDetector, MalformedLinesNameFileAndLine) {
  const std::string bad[] = {
      "10.0 1 2 3 12\n",                   // too few columns
      "10.0 1 2 3 12 18 0.5\n10.0 x 2 3 12 18 0.5\n",  // not a number, line 2
      "10.0 1 12 3 2 18 0.5\n",             // corners swapped
      "10.0 1 nan 3 12 18 0.5\n",
  };
  const int lines[] = {1, 2, 1, 1};
  for (int i = 0; i < 4; ++i) {
    GtDetector::Options o;
    o.gt_folder = makeGt("pf2_gt_bad" + std::to_string(i), bad[i]);
    try {
      GtDetector detector(o);
      ADD_FAILURE() << "no error for case " << i;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(o.gt_folder + "/boxes.txt:" + std::to_string(lines[i]) + ":"),
                std::string::npos)
          << e.what();
    }
  }
  GtDetector::Options missing;
  missing.gt_folder = testing::TempDir() + "pf2_gt_does_not_exist";
  EXPECT_THROW(GtDetector detector(missing), Error);
}

TEST(GtDetector, UnreadableOrWrongSizedMaskIsAnError) {
  GtDetector::Options o;
  o.gt_folder = makeGt("pf2_gt_badmask", kBoxes);
  o.provide_mask = true;
  writeText(o.gt_folder + "/masks/10.000000.png", "not a png");
  GtDetector detector(o);
  try {
    detector.detect(frameAt(10.0));
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("10.000000.png"), std::string::npos) << e.what();
  }
  cv::imwrite(o.gt_folder + "/masks/10.033333.png", cv::Mat::zeros(10, 10, CV_16U));
  EXPECT_THROW(detector.detect(frameAt(10.033333)), Error);
}

TEST(GtDetector, DegradationIsApplied) {
  GtDetector::Options o;
  o.gt_folder = makeGt("pf2_gt_degraded", kBoxes);
  o.degradation.shrink = 0.5;
  GtDetector detector(o);
  const Detections d = detector.detect(frameAt(10.0));
  ASSERT_EQ(d.people.size(), 2u);
  EXPECT_FLOAT_EQ(d.people[0].box.width(), 5.f);
  EXPECT_FLOAT_EQ(d.people[0].box.height(), 7.5f);
  EXPECT_FLOAT_EQ(d.people[0].box.x_ul, 4.5f);  // box (2, 3)-(12, 18)
}

}  // namespace
}  // namespace pf2
