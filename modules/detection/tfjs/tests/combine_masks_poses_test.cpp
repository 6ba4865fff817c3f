// The merge step of the "learned" detector on hand-made masks and poses (no model needed).
#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "pf2/detection/learned_person_detector.h"

namespace pf2 {
namespace {

constexpr int kW = 200, kH = 100;

PersonDetection component(const cv::Mat& mask) {
  PersonDetection c;
  c.mask = mask;
  const cv::Rect r = cv::boundingRect(mask);
  c.box = {static_cast<float>(r.x), static_cast<float>(r.y), static_cast<float>(r.x + r.width),
           static_cast<float>(r.y + r.height)};
  c.score = 0.9f;
  return c;
}

// A pose: box and a column of confident keypoints at u.
PersonDetection pose(float x_ul, float x_lr, float u) {
  PersonDetection p;
  p.box = {x_ul, 10, x_lr, 90};
  p.score = 0.4f;
  for (int k = 0; k < 17; ++k) p.keypoints.push_back({u, 15.f + 4 * k, 0.8f});
  return p;
}

TEST(CombineMasksAndPoses, SplitsASharedComponentByNearestKeypoint) {
  // Two bodies (x 20..70 and 110..160) joined by a bridge: one selfie component.
  cv::Mat mask(kH, kW, CV_8U, cv::Scalar(0));
  cv::rectangle(mask, cv::Rect(20, 10, 50, 80), cv::Scalar(255), cv::FILLED);
  cv::rectangle(mask, cv::Rect(110, 10, 50, 80), cv::Scalar(255), cv::FILLED);
  cv::rectangle(mask, cv::Rect(70, 40, 40, 10), cv::Scalar(255), cv::FILLED);
  const cv::Mat probability(kH, kW, CV_32F, cv::Scalar(0.8));
  LearnedPersonDetector::Options options;
  options.box_margin = 0.5f;  // both claims reach into the bridge, so it is contested
  const std::vector<PersonDetection> people =
      combineMasksAndPoses({component(mask)}, {pose(20, 70, 45), pose(110, 160, 135)}, probability, options);
  ASSERT_EQ(people.size(), 2u);
  // Every mask pixel goes to exactly one person, split at the midpoint between the keypoints (u = 90).
  EXPECT_EQ(cv::countNonZero(people[0].mask & people[1].mask), 0);
  EXPECT_EQ(cv::countNonZero((people[0].mask | people[1].mask) != mask), 0);
  EXPECT_EQ(cv::countNonZero(people[0].mask(cv::Rect(91, 0, kW - 91, kH))), 0);
  EXPECT_EQ(cv::countNonZero(people[1].mask(cv::Rect(0, 0, 90, kH))), 0);
  EXPECT_EQ(cv::countNonZero(people[0].mask), 50 * 80 + 21 * 10);
  // Boxes cover the mask; keypoints are kept; score is the mean mask probability.
  EXPECT_FLOAT_EQ(people[0].box.x_ul, 20.f);
  EXPECT_FLOAT_EQ(people[0].box.x_lr, 91.f);
  EXPECT_FLOAT_EQ(people[1].box.x_ul, 91.f);
  EXPECT_FLOAT_EQ(people[1].box.x_lr, 160.f);
  EXPECT_EQ(people[1].keypoints.size(), 17u);
  EXPECT_NEAR(people[0].score, 0.8f, 1e-6f);
}

// The selfie model marks blurred or plain scenes as "person", so a mask no confident pose
// supports is dropped; a confident pose over no mask stays a box; a weak pose is no person.
TEST(CombineMasksAndPoses, DropsUnsupportedMasksAndWeakPosesKeepsMasklessPoses) {
  cv::Mat mask(kH, kW, CV_8U, cv::Scalar(0));
  cv::rectangle(mask, cv::Rect(20, 10, 30, 80), cv::Scalar(255), cv::FILLED);
  const cv::Mat probability(kH, kW, CV_32F, cv::Scalar(0.7));
  PersonDetection weak = pose(15, 55, 35);  // over the mask, but only 3 confident keypoints
  for (size_t k = 3; k < weak.keypoints.size(); ++k) weak.keypoints[k].score = 0.2f;
  std::vector<PersonDetection> unclaimed;
  const std::vector<PersonDetection> people = combineMasksAndPoses(
      {component(mask)}, {weak, pose(140, 180, 160)}, probability, LearnedPersonDetector::Options(), &unclaimed);
  ASSERT_EQ(people.size(), 1u);
  EXPECT_TRUE(people[0].mask.empty());
  EXPECT_EQ(people[0].keypoints.size(), 17u);
  EXPECT_FLOAT_EQ(people[0].box.x_ul, 140.f);
  EXPECT_FLOAT_EQ(people[0].score, 1.f);  // seen whole: all 17 keypoints confident, above MoveNet's 0.4
  // The unsupported mask is not a person but is handed on as a candidate, whole.
  ASSERT_EQ(unclaimed.size(), 1u);
  EXPECT_EQ(cv::countNonZero(unclaimed[0].mask != mask), 0);
  EXPECT_NEAR(unclaimed[0].score, 0.7f, 1e-6f);

  // With the weak pose's fourth keypoint confident it supports the mask and takes all of it.
  weak.keypoints[3].score = 0.3f;
  const std::vector<PersonDetection> supported =
      combineMasksAndPoses({component(mask)}, {weak}, probability, LearnedPersonDetector::Options());
  ASSERT_EQ(supported.size(), 1u);
  EXPECT_EQ(cv::countNonZero(supported[0].mask != mask), 0);
  EXPECT_NEAR(supported[0].score, 0.7f, 1e-6f);
}

// A pose without mask scores MoveNet's score, or the share of its confident keypoints when it is
// seen whole (at least whole_pose_keypoints of them): the filter uses boxes above 0.5, and MoveNet
// scores small people in dark clothes below that with every keypoint found.
TEST(CombineMasksAndPoses, APoseSeenWholeScoresItsShareOfConfidentKeypoints) {
  const cv::Mat probability(kH, kW, CV_32F, cv::Scalar(0.0));
  const LearnedPersonDetector::Options options;
  ASSERT_EQ(options.whole_pose_keypoints, 14);
  for (const int confident : {4, 13, 14, 17}) {
    PersonDetection p = pose(140, 180, 160);
    for (size_t k = static_cast<size_t>(confident); k < p.keypoints.size(); ++k) p.keypoints[k].score = 0.1f;
    const std::vector<PersonDetection> people = combineMasksAndPoses({}, {p}, probability, options);
    ASSERT_EQ(people.size(), 1u) << confident;
    EXPECT_TRUE(people[0].mask.empty());
    const float expected = confident >= 14 ? confident / 17.f : 0.4f;
    EXPECT_NEAR(people[0].score, expected, 1e-6f) << confident << " confident keypoints";
  }
  // A pose MoveNet scores higher than its share keeps MoveNet's score.
  PersonDetection sure = pose(140, 180, 160);
  for (size_t k = 14; k < sure.keypoints.size(); ++k) sure.keypoints[k].score = 0.1f;
  sure.score = 0.95f;
  EXPECT_FLOAT_EQ(combineMasksAndPoses({}, {sure}, probability, options)[0].score, 0.95f);
}

// A component covering most of the image (blur, a plain wall) is cut to the box of the person
// touching it, so a real person next to it does not take the whole image.
TEST(CombineMasksAndPoses, CutsAnImplausiblyLargeComponentToThePersonsBox) {
  cv::Mat mask(kH, kW, CV_8U, cv::Scalar(0));
  cv::rectangle(mask, cv::Rect(0, 0, 180, kH), cv::Scalar(255), cv::FILLED);  // 90 % of the image
  const cv::Mat probability(kH, kW, CV_32F, cv::Scalar(0.9));
  LearnedPersonDetector::Options options;
  options.box_margin = 0.f;
  std::vector<PersonDetection> people =
      combineMasksAndPoses({component(mask)}, {pose(20, 70, 45)}, probability, options);
  ASSERT_EQ(people.size(), 1u);
  EXPECT_EQ(cv::countNonZero(people[0].mask), 50 * 80);  // the box x 20..70, y 10..90
  EXPECT_EQ(cv::countNonZero(people[0].mask(cv::Rect(20, 10, 50, 80))), 50 * 80);
  EXPECT_EQ(cv::countNonZero(mask), 180 * kH);  // the input component is left alone
  std::vector<PersonDetection> unclaimed;
  combineMasksAndPoses({component(mask)}, {}, probability, options, &unclaimed);
  EXPECT_TRUE(unclaimed.empty());  // without a person, too large to be a candidate

  options.max_component_fraction = 1.0;  // no limit: the person takes the whole component
  people = combineMasksAndPoses({component(mask)}, {pose(20, 70, 45)}, probability, options);
  ASSERT_EQ(people.size(), 1u);
  EXPECT_EQ(cv::countNonZero(people[0].mask), 180 * kH);
}

TEST(AddCropMasks, JoinsCropMasksWithinEachPosedPersonsClaim) {
  // A crop mask over x 0..199; a posed person boxed at x 40..80 with a mask at x 50..60, a posed
  // person without a mask at x 120..160 and a candidate region without keypoints.
  const cv::Mat crops(kH, kW, CV_8U, cv::Scalar(255));
  std::vector<PersonDetection> people{pose(40, 80, 60), pose(120, 160, 140), PersonDetection{}};
  people[0].mask = cv::Mat(kH, kW, CV_8U, cv::Scalar(0));
  people[0].mask(cv::Rect(50, 10, 10, 80)).setTo(255);
  people[2].box = {0, 0, 30, 30};
  addCropMasks(crops, 0.1f, &people);
  // The claim: the box enlarged by a tenth of its size (4 px across, 8 px down) on each side.
  EXPECT_EQ(cv::boundingRect(people[0].mask), cv::Rect(36, 2, 48, 96));
  ASSERT_FALSE(people[1].mask.empty());
  EXPECT_EQ(cv::boundingRect(people[1].mask), cv::Rect(116, 2, 48, 96));
  EXPECT_TRUE(people[2].mask.empty());
  EXPECT_FLOAT_EQ(people[1].box.x_ul, 120.f);  // boxes stay as they were
}

}  // namespace
}  // namespace pf2
