#include "pf2/detection/hog_detector.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

// A plain frame has no person in it; a frame without colour gives nothing; bad options throw.
// (How well HOG sees rendered people is measured on pf2_synth sequences in docs/BENCHMARKS.md.)
TEST(HogDetector, NothingInAnEmptyRoomAndScoresInRange) {
  HogDetector detector;
  EXPECT_EQ(detector.name(), "hog");
  Frame frame;
  frame.rgb = cv::Mat(240, 320, CV_8UC3, cv::Scalar(90, 100, 110));
  EXPECT_TRUE(detector.detect(frame).people.empty());
  Frame none;
  EXPECT_TRUE(detector.detect(none).people.empty());
  // A dark upright silhouette on a light background: whatever HOG makes of it, boxes lie in the
  // image and scores in (0, 1).
  cv::Mat image(240, 320, CV_8UC3, cv::Scalar(200, 200, 200));
  cv::ellipse(image, cv::Point(160, 60), cv::Size(12, 15), 0, 0, 360, cv::Scalar(30, 30, 30), -1);
  cv::rectangle(image, cv::Rect(140, 75, 40, 70), cv::Scalar(30, 30, 30), -1);
  cv::rectangle(image, cv::Rect(143, 145, 14, 70), cv::Scalar(30, 30, 30), -1);
  cv::rectangle(image, cv::Rect(163, 145, 14, 70), cv::Scalar(30, 30, 30), -1);
  frame.rgb = image;
  for (const auto& p : detector.detect(frame).people) {
    EXPECT_GT(p.score, 0.f);
    EXPECT_LT(p.score, 1.f);
    EXPECT_GE(p.box.x_ul, 0.f);
    EXPECT_LE(p.box.x_lr, 320.f);
    EXPECT_LE(p.box.y_lr, 240.f);
  }
  HogDetector::Options bad;
  bad.pyramid_scale = 1.0;
  EXPECT_THROW(HogDetector d(bad), Error);
}

// A real frame with two people (TUM fr3/walking_xyz) and its reference person mask: HOG must find
// someone, and every box it reports must lie mostly on a person (the one it finds: 55 %).
TEST(HogDetector, FindsAPersonOnARealFrameWithPeople) {
  const std::string dir = std::string(PF2_SHARED_DATA) + "/tum_fr3_walking_xyz_1frame/";
  Frame frame;
  frame.rgb = cv::imread(dir + "1341846313.553992.png");
  const cv::Mat mask = cv::imread(dir + "1341846313.553992_person_mask.png", cv::IMREAD_GRAYSCALE);
  if (frame.rgb.empty() || mask.empty()) GTEST_SKIP() << "no " << dir;
  const std::vector<PersonDetection> people = HogDetector().detect(frame).people;
  ASSERT_FALSE(people.empty());
  for (const PersonDetection& p : people) {
    const cv::Rect box = cv::Rect(cv::Point(cvRound(p.box.x_ul), cvRound(p.box.y_ul)),
                                  cv::Point(cvRound(p.box.x_lr), cvRound(p.box.y_lr))) &
                         cv::Rect(0, 0, mask.cols, mask.rows);
    ASSERT_GT(box.area(), 0);
    EXPECT_GT(cv::countNonZero(mask(box)), 0.4 * box.area()) << "box " << box;
  }
}

}  // namespace
}  // namespace pf2
