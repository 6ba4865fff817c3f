#include "pf2/slam/keyframe_prediction.h"

#include <cstdlib>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/registration/rgbd_odometry.h"

namespace pf2 {
namespace {

// A keyframe looking at a wall `depth` metres ahead, optionally with a hole (a removed person) in
// the middle.
Keyframe wallKeyframe(const CameraIntrinsics& k, double depth, bool hole) {
  Keyframe keyframe;
  keyframe.intrinsics = k;
  keyframe.depth = cv::Mat(k.height, k.width, CV_16U,
                           cv::Scalar(depth * Keyframe::kDepthUnitsPerMetre));
  if (hole) keyframe.depth(cv::Rect(k.width / 2 - 10, k.height / 2 - 10, 20, 20)).setTo(0);
  keyframe.gray = cv::Mat(k.height, k.width, CV_8U, cv::Scalar(100));
  return keyframe;
}

TEST(KeyframeDepthPrediction, FarthestKeyframeDepthSeenFromThePose) {
  const CameraIntrinsics k = CameraIntrinsics::tumFreiburg3().scaled(0.25);  // 160x120
  KeyframeMap map;
  KeyframeDepthPrediction prediction;
  EXPECT_TRUE(prediction.predict(map, Eigen::Isometry3d::Identity(), k).empty());  // no keyframe yet
  map.add(wallKeyframe(k, 2.0, true), Eigen::Isometry3d::Identity());
  // A second keyframe 0.5 m closer to the wall sees it at 1.5 m: the same wall, the same prediction.
  Eigen::Isometry3d T_w_k1 = Eigen::Isometry3d::Identity();
  T_w_k1.translation().z() = 0.5;
  map.add(wallKeyframe(k, 1.5, false), T_w_k1);

  const cv::Mat at_start = prediction.predict(map, Eigen::Isometry3d::Identity(), k);
  ASSERT_EQ(at_start.size(), cv::Size(k.width, k.height));
  EXPECT_NEAR(at_start.at<float>(10, 10), 2.0f, 1e-3);
  // The first keyframe's hole is filled by the second (it is smaller there, seen from closer).
  EXPECT_NEAR(at_start.at<float>(k.height / 2, k.width / 2), 2.0f, 1e-3);
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  T_w_c.translation().z() = 0.8;
  EXPECT_NEAR(prediction.predict(map, T_w_c, k).at<float>(60, 40), 1.2f, 1e-3);

  // With lens distortion the prediction lands on the distorted pixel grid: a vertical depth edge
  // near the left border is straight in the rectified prediction and bent (barrel) in the raw one.
  // (Full resolution: the bend is about 3 pixels between the top row and the middle one.)
  const CameraIntrinsics fr1 = CameraIntrinsics::tumFreiburg1();
  KeyframeMap edge_map;
  Keyframe edge = wallKeyframe(fr1, 2.0, false);
  edge.depth.colRange(0, 60).setTo(3.0 * Keyframe::kDepthUnitsPerMetre);
  edge_map.add(edge, Eigen::Isometry3d::Identity());
  KeyframeDepthPrediction::Options options;
  options.downsample = 1;
  KeyframeDepthPrediction rectified(options);
  options.distortion = kTumFreiburg1Distortion;
  KeyframeDepthPrediction distorted(options);
  const auto edge_column = [](const cv::Mat& depth, int row) {
    int u = 0;
    while (u < depth.cols && !(depth.at<float>(row, u) > 0.f && depth.at<float>(row, u) < 2.5f)) ++u;
    return u;
  };
  const cv::Mat straight = rectified.predict(edge_map, Eigen::Isometry3d::Identity(), fr1);
  const cv::Mat bent = distorted.predict(edge_map, Eigen::Isometry3d::Identity(), fr1);
  EXPECT_EQ(edge_column(straight, 10), edge_column(straight, 255));
  EXPECT_GE(std::abs(edge_column(bent, 10) - edge_column(bent, 255)), 2);
  EXPECT_NEAR(bent.at<float>(255, 318), 2.0f, 1e-3);  // the centre stays

  KeyframeDepthPrediction::Options bad;
  bad.keyframes = 0;
  EXPECT_THROW(KeyframeDepthPrediction{bad}, Error);
}

}  // namespace
}  // namespace pf2
