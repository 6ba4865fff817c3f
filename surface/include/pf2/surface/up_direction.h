#pragma once
// UpDirectionEstimator: the world's up direction (against gravity) from the static scene's
// horizontal surfaces, floor and table tops, seen in the first frames of a run.
//
// pf2_slam's world frame is the first camera's, whose -y is "up" only when that camera is level;
// pf2_synth's camera looks 10-11 degrees down, as most hand-held and robot cameras do. The body
// fitter's upright prior (without it the fits leaned 16 degrees, and legs outside the image with
// them) and its initial orientation need the real up; stats.json reports it.
//
// Per frame: the surface normal at every stride-th pixel (cross product of the back-projected
// neighbours right and below, across no depth step), turned into the world frame; those within
// max_angle of the current guess (the fallback at first) are the horizontal-surface candidates,
// narrowed to the ones within fine_angle of their mean, then of the new mean. A frame with fewer
// than min_frame_normals such normals says nothing (no floor in view, or too little). The sum of
// the kept normals over frames gives the estimate; once it holds settled_normals, it no longer
// changes (the same up for the whole run, and no more cost).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"

namespace pf2 {

class UpDirectionEstimator {
 public:
  struct Options {
    int stride_px = 8;               // [1, 64] px between sampled pixels (and to their neighbours)
    double max_depth = 5.0;          // (0, 100] m: farther depth is too noisy for a normal
    double max_depth_step = 0.05;    // (0, 1]: neighbours differing by more than this x depth lie across an edge
    double max_angle = 0.6;          // (0, pi/2) rad from the guess (35 degrees): a camera within this of level
    double fine_angle = 0.12;        // (0, max_angle] rad from the candidates' mean (7 degrees)
    int min_frame_normals = 150;     // >= 1: a frame with fewer horizontal normals is not used
    int settled_normals = 3000;      // >= 1: kept normals after which the estimate is final
  };

  // `fallback_w`: the up used until a frame shows horizontal surfaces (the first camera's -y when
  // the world is the first camera's frame), unit or not (it is normalised); throws pf2::Error for
  // options out of range or a zero fallback.
  UpDirectionEstimator(const Options& options, const Eigen::Vector3d& fallback_w = Eigen::Vector3d(0, -1, 0));
  UpDirectionEstimator() : UpDirectionEstimator(Options()) {}

  // Takes one frame's static depth (CV_32F metres, 0 = none; people removed) seen from T_w_c.
  // Returns whether the frame was used. Does nothing once settled. NOT thread safe.
  bool update(const cv::Mat& depth, const CameraIntrinsics& intrinsics, const Eigen::Isometry3d& T_w_c);

  // The world's up, unit: the estimate, or the fallback before any frame was used. NOT thread safe
  // against update().
  Eigen::Vector3d up_w() const;
  // Whether a frame was used / the estimate is final. NOT thread safe against update().
  bool estimated() const { return normals_ > 0; }
  bool settled() const { return normals_ >= options_.settled_normals; }

 private:
  Options options_;
  Eigen::Vector3d fallback_w_;
  Eigen::Vector3d sum_w_ = Eigen::Vector3d::Zero();  // of the kept unit normals
  long normals_ = 0;
};

}  // namespace pf2
