// MoveNet MultiPose decoding on hand-made heads (no model needed).
#include <cmath>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/detection/movenet_detector.h"

namespace pf2 {
namespace {

constexpr int kGh = 12, kGw = 16, kK = 17;
constexpr float kCell = 10.f;  // pixels per grid cell

cv::Mat blob(int channels, float fill) {
  const int shape[] = {1, channels, kGh, kGw};
  return cv::Mat(4, shape, CV_32F, cv::Scalar(fill));
}
float& at(cv::Mat& b, int c, int y, int x) { return b.ptr<float>(0, c)[y * kGw + x]; }

// One person centred at cell (y 6, x 8); keypoint k is regressed to (6 + dy_k, 8 + dx_k), where
// its heatmap peaks (0.8) with a sub-cell offset (0.25, -0.25). Each heatmap also has a stronger
// peak outside the box and a slightly stronger one inside the box but 3 cells from the regressed
// point: both must lose.
std::vector<cv::Mat> makeHeads() {
  cv::Mat centre = blob(1, 0.01f), heat = blob(kK, 0.0f), regress = blob(2 * kK, 0.0f),
          offset = blob(2 * kK, 0.0f), box_size = blob(2, 0.0f), box_offset = blob(2, 0.0f);
  at(centre, 0, 6, 8) = 0.9f;
  at(box_size, 0, 6, 8) = 8.f;     // h: rows 2.5 .. 10.5 after the offset
  at(box_size, 1, 6, 8) = 6.f;     // w: cols 4.5 .. 10.5
  at(box_offset, 0, 6, 8) = 0.5f;
  at(box_offset, 1, 6, 8) = -0.5f;
  for (int k = 0; k < kK; ++k) {
    const int dy = k % 5 - 2, dx = k % 3 - 1;
    at(regress, 2 * k, 6, 8) = static_cast<float>(dy);
    at(regress, 2 * k + 1, 6, 8) = static_cast<float>(dx);
    at(heat, k, 6 + dy, 8 + dx) = 0.8f;
    at(offset, 2 * k, 6 + dy, 8 + dx) = 0.25f;
    at(offset, 2 * k + 1, 6 + dy, 8 + dx) = -0.25f;
    at(heat, k, 0, 0) = 0.95f;                   // outside the box
    at(heat, k, 6 + dy, 8 + dx + (dx > 0 ? -3 : 3)) = 0.85f;  // inside, but far from the regressed point
  }
  return {centre, heat, regress, offset, box_size, box_offset};
}

TEST(MoveNetDecode, FindsThePersonItsBoxAndKeypoints) {
  const std::vector<PersonDetection> people = decodeMoveNet(makeHeads(), kCell, kCell, MoveNetDetector::Options());
  // The flat 0.01 background also has local maxima; their scores are far below min_person_score.
  ASSERT_EQ(people.size(), 1u);
  const PersonDetection& p = people[0];
  EXPECT_NEAR(p.box.x_ul, 45.f, 1e-4f);
  EXPECT_NEAR(p.box.x_lr, 105.f, 1e-4f);
  EXPECT_NEAR(p.box.y_ul, 25.f, 1e-4f);
  EXPECT_NEAR(p.box.y_lr, 105.f, 1e-4f);
  ASSERT_EQ(p.keypoints.size(), 17u);
  for (int k = 0; k < kK; ++k) {
    const int dy = k % 5 - 2, dx = k % 3 - 1;
    EXPECT_NEAR(p.keypoints[k].u, (8 + dx - 0.25f) * kCell, 1e-4f) << "keypoint " << k;
    EXPECT_NEAR(p.keypoints[k].v, (6 + dy + 0.25f) * kCell, 1e-4f) << "keypoint " << k;
    EXPECT_NEAR(p.keypoints[k].score, 0.8f, 1e-6f) << "keypoint " << k;
  }
  EXPECT_NEAR(p.score, 0.9f * 0.8f, 1e-6f);  // centre x mean confident keypoint score
}

TEST(MoveNetDecode, DropsWeakPeopleAndRejectsWrongShapes) {
  std::vector<cv::Mat> heads = makeHeads();
  MoveNetDetector::Options options;
  options.min_person_score = 0.75f;  // above the person's 0.72
  EXPECT_TRUE(decodeMoveNet(heads, kCell, kCell, options).empty());
  options.min_person_score = 0.0f;   // keeps the background maxima too, up to max_people
  options.max_people = 3;
  EXPECT_EQ(decodeMoveNet(heads, kCell, kCell, options).size(), 3u);

  heads.pop_back();
  EXPECT_THROW(decodeMoveNet(heads, kCell, kCell, MoveNetDetector::Options()), Error);
  heads = makeHeads();
  heads[2] = blob(17, 0.f);  // regression needs 34 channels
  EXPECT_THROW(decodeMoveNet(heads, kCell, kCell, MoveNetDetector::Options()), Error);
}

}  // namespace
}  // namespace pf2
