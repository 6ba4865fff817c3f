#pragma once
// Keyframes and the map of them that tracking, loop closing and the mapper share.
//
// A Keyframe is stored compactly (grey image, 16-bit depth, ORB features: about 1 MB at 640x480)
// so that thousands fit in memory; RgbdOdometry::prepare(const Keyframe&) rebuilds its pyramids
// when a loop or a relocalisation needs it. The pose lives in the KeyframeMap, not in the
// keyframe, because the pose graph moves it.
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"
#include "pf2/registration/odometry_frame.h"

namespace pf2 {

struct Keyframe {
  static constexpr double kDepthUnitsPerMetre = 5000.0;  // depth storage (TUM's 0.2 mm steps)

  int id = -1;            // assigned by KeyframeMap::add, 0, 1, 2, ... in order of creation
  int frame_index = -1;   // Frame::index it was made from
  double timestamp = 0.0; // Frame::timestamp, seconds
  CameraIntrinsics intrinsics;
  cv::Mat gray;   // CV_8U full-resolution grey image (rectified if the odometry undistorts)
  cv::Mat depth;  // CV_16U, kDepthUnitsPerMetre per metre, 0 = unusable (people already removed)
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;                           // CV_8U ORB rows
  std::vector<Eigen::Vector3d> keypoint_points;  // p_k of each keypoint, metres
};

// The compact copy of a prepared reference frame (which must have features).
Keyframe makeKeyframe(const OdometryFrame& frame);

// Keyframes with their world poses T_w_k. Thread safe: every method locks; keyframes are
// immutable once added and handed out as shared pointers, so readers never block writers long.
class KeyframeMap {
 public:
  // Adds the keyframe with pose T_w_k and returns its id (keyframe.id is overwritten).
  int add(Keyframe keyframe, const Eigen::Isometry3d& T_w_k);
  // Adds the keyframe at T_w_ref * T_ref_k with T_w_ref read under the same lock, so it stays
  // consistent with a concurrent updatePoses(). Throws pf2::Error for an unknown reference_id.
  int addRelative(Keyframe keyframe, int reference_id, const Eigen::Isometry3d& T_ref_k);
  size_t size() const;
  // Throws pf2::Error for an unknown id.
  std::shared_ptr<const Keyframe> keyframe(int id) const;
  Eigen::Isometry3d pose(int id) const;
  std::map<int, Eigen::Isometry3d> poses() const;
  // Replaces the poses of the given keyframes (pose-graph corrections) and bumps revision().
  // Keyframes newer than the newest given one (added by tracking while the graph was being
  // optimised) move rigidly with that newest one, so the map stays consistent. Unknown ids are
  // ignored.
  void updatePoses(const std::map<int, Eigen::Isometry3d>& T_w_k);
  // Increases by one with every updatePoses(); lets a mapper poll for corrections.
  uint64_t revision() const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<const Keyframe>> keyframes_;
  std::vector<Eigen::Isometry3d> poses_;
  uint64_t revision_ = 0;
};

// Decides when the current frame becomes a new keyframe: when it has moved or turned far enough
// from its keyframe, or when the overlap (dense inlier ratio) has dropped. Stateless, thread safe.
class KeyframeSelector {
 public:
  struct Options {
    double max_translation = 0.10;  // metres from the keyframe
    double max_rotation = 0.10;     // radians from the keyframe (5.7 degrees)
    double min_inlier_ratio = 0.55; // dense inliers / samples against the keyframe
    int max_frames = 0;             // frames since the keyframe; 0 = no limit
  };
  KeyframeSelector();
  explicit KeyframeSelector(const Options& options);
  const Options& options() const { return options_; }
  bool needsKeyframe(const Eigen::Isometry3d& T_k_c, double inlier_ratio,
                     int frames_since_keyframe) const;

 private:
  Options options_;
};

}  // namespace pf2
