#pragma once
// FloorEstimator: the floor's height along the world's up, from the static depth of the frames.
//
// Every stride-th pixel's point where the surface runs level (to its neighbours stride pixels right
// and below: no depth step, a rise under 14 degrees) is turned into the world and its height along
// up counted in bins of bin_size; a floor or a table top piles them into a few bins. The floor is
// the lowest pile: the lowest three bins that together hold at least min_share of all counted
// points (table tops lie above it, the few points below are noise), followed up to the pile's top
// and refined to the mean height within two bins of that. Once settled_points points were counted,
// it no longer changes.
//
// People stand on it and are no part of it: pf2_slam's filter keeps depth on it as static
// (PredictedDepthEvidence::setStaticPlane) where no keyframe has seen the floor yet.
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"

namespace pf2 {

class FloorEstimator {
 public:
  struct Options {
    int stride_px = 8;            // [1, 64] px between sampled pixels
    double max_depth = 5.0;       // (0, 100] m: farther depth is too noisy
    double bin_size = 0.02;       // (0, 0.5] m
    double range = 5.0;           // (0, 50] m: heights within +-range of the world origin are counted
    double min_share = 0.05;      // (0, 1]: three floor bins hold at least this share of the points
    int min_points = 2000;        // >= 1: no floor before this many points were counted
    int settled_points = 200000;  // >= min_points: points after which the estimate is final
  };

  FloorEstimator() : FloorEstimator(Options()) {}
  // Throws pf2::Error for options out of range.
  explicit FloorEstimator(const Options& options);

  // Counts one frame's static depth (CV_32F metres, 0 = none; people removed) seen from T_w_c with
  // the world's unit up `up_w`, which must stay the same between calls (pass it once it is
  // final). Does nothing once settled. NOT thread safe.
  void update(const cv::Mat& depth, const CameraIntrinsics& intrinsics, const Eigen::Isometry3d& T_w_c,
              const Eigen::Vector3d& up_w);

  // Whether a floor was found, and its height along up_w (metres, world frame: a point p_w lies
  // up_w . p_w - height() above it). NOT thread safe against update().
  bool found() const { return found_; }
  double height() const { return height_; }

 private:
  long window(size_t i) const;
  void locate();

  Options options_;
  std::vector<long> bins_;
  long points_ = 0;
  bool found_ = false;
  double height_ = 0;
};

}  // namespace pf2
