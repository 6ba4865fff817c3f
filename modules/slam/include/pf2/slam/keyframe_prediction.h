#pragma once
// The static depth a camera should see, predicted from the newest keyframes: their human-free
// depth is the map's most recent view of the static scene. Each keyframe is moved into the
// predicted camera pose and, per pixel, the farthest prediction is kept: a static surface seen at
// depth d along a ray means that the space in front of it was empty, so anything measured well in
// front of d is moving (the free-space test behind ReFusion's and StaticFusion's dynamic masks).
// Taking the farthest keeps a person left in one keyframe (a missed detection) from hiding the
// wall behind them in the other.
//
// pf2_slam hands the prediction to the Dual-BBox filter's geometric addition
// (PredictedDepthEvidence) before the frame is tracked, with the constant-velocity pose guess, so
// people the detector missed are removed from this frame's depth and never reach a keyframe.
#include <map>
#include <memory>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"
#include "pf2/registration/keyframe.h"

namespace pf2 {

class KeyframeDepthPrediction {
 public:
  struct Options {
    int keyframes = 10;  // newest keyframes predicted from, >= 1: more cover more of the static
                         // scene people hid in one keyframe (with filter.keep_static, 2 -> 6:
                         // Bonn crowd 3.2 -> 1.96 cm, pf2_synth halfsphere retention 81 -> 90 %;
                         // 6 -> 10: a close person missed in six keyframes in a row is seen
                         // through in an older one, pf2_synth xyz with 5 people 24 -> 10 mm, the
                         // hard cases' removal 97.9 / 94.2 -> 98.0 / 94.8 %; 1.3 ms more a frame)
    int downsample = 2;  // the warp runs at 1/downsample resolution (nearest-neighbour upsampled
                         // back): a 0.15 m free-space margin does not need every pixel; 1 = full
    // Lens distortion of the camera (OpenCV k1 k2 p1 p2 k3, as RgbdOdometry::Options::distortion):
    // keyframes hold rectified depth, the frames to compare with do not, so the prediction is
    // moved onto the distorted pixel grid. Empty = rectified images.
    std::vector<double> distortion;
  };

  KeyframeDepthPrediction() : KeyframeDepthPrediction(Options()) {}
  // Throws pf2::Error when an option is out of range.
  explicit KeyframeDepthPrediction(const Options& options);

  // CV_32F metres at intrinsics' size, 0 where no keyframe predicts anything; an empty image when
  // the map has no keyframe yet. T_w_c: the pose the view is predicted for. NOT thread safe (keeps
  // the converted keyframe depths between calls); the map itself may be written concurrently.
  cv::Mat predict(const KeyframeMap& map, const Eigen::Isometry3d& T_w_c,
                  const CameraIntrinsics& intrinsics);

 private:
  // Keyframe depth in metres at the warp's resolution, converted once per keyframe.
  const cv::Mat& depthOf(const Keyframe& keyframe);
  // A rectified image moved onto the distorted pixel grid (nearest neighbour).
  cv::Mat distort(const cv::Mat& rectified, const CameraIntrinsics& intrinsics);

  Options options_;
  std::map<int, cv::Mat> depth_by_id_;
  cv::Mat rectified_of_pixel_;  // CV_32FC2: each distorted pixel's rectified position
  CameraIntrinsics map_intrinsics_;
};

}  // namespace pf2
