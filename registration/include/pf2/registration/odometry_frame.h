#pragma once
// The data one RGB-D frame carries through tracking: image pyramids of intensity and depth, the
// reference-only maps (gradients, points, normals) a keyframe needs, and its ORB features.
// A data object: engines (RgbdOdometry, FeatureAligner) fill it, nothing here computes.
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"

namespace pf2 {

struct OdometryLevel {
  CameraIntrinsics intrinsics;  // scaled to this level
  cv::Mat intensity;            // CV_32F, grey value in [0, 1]
  cv::Mat depth;                // CV_32F, metres, 0 = unusable (no measurement, person, out of range)
  // Filled only for reference frames (RgbdOdometry::makeReference):
  cv::Mat gradient_x;  // CV_32F, d intensity / d u, per pixel
  cv::Mat gradient_y;  // CV_32F, d intensity / d v, per pixel
  cv::Mat normals;     // CV_32FC3, unit normals in the camera frame, (0,0,0) where unknown
};

struct OdometryFrame {
  double timestamp = 0.0;
  int index = -1;
  std::vector<OdometryLevel> levels;  // level 0 = full resolution
  cv::Mat gray;                       // CV_8U, level 0 grey image (feature extraction)
  cv::Mat feature_mask;               // CV_8U, 255 where features may be taken (depth valid, no person)
  int valid_depth_pixels = 0;         // level 0 pixels with usable depth
  bool is_reference = false;          // gradients, normals and features present

  // Filled by FeatureAligner::extract; only keypoints with usable depth are kept.
  bool has_features = false;
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;                           // CV_8U ORB, one row per keypoint
  std::vector<Eigen::Vector3d> keypoint_points;  // p_c of each keypoint, metres
};

}  // namespace pf2
