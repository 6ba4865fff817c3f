#pragma once
// Sparse, robust coarse alignment of two RGB-D frames: ORB features with depth, brute-force
// Hamming matching with Lowe's ratio test, and a 3D-3D RANSAC whose minimal and final models are
// Umeyama's closed-form rigid fit. Used for the coarse pose of the odometry, for relocalisation
// and for loop verification, where no prior pose exists.
#include <Eigen/Geometry>

#include "pf2/registration/odometry_frame.h"

namespace pf2 {

struct SparseAlignment {
  bool valid = false;                                       // enough inliers for a trusted pose
  Eigen::Isometry3d T_ref_cur = Eigen::Isometry3d::Identity();  // current camera -> reference camera
  int matches = 0;                                          // matches after the ratio test
  int inliers = 0;                                          // RANSAC inliers of the final model
  double inlier_rmse = 0.0;                                 // metres, over the inliers
};

class FeatureAligner {
 public:
  struct Options {
    int max_features = 600;           // ORB keypoints detected per frame (before the depth check)
    int fast_threshold = 12;          // ORB FAST threshold, grey levels
    int pyramid_levels = 4;           // ORB scale levels (factor 1.2 between them)
    double ratio = 0.8;               // Lowe ratio: best / second-best Hamming distance below this
    int max_hamming = 64;             // matches with a larger Hamming distance are dropped, bits
    int ransac_iterations = 200;      // 3-point hypotheses tried
    double inlier_distance = 0.03;    // metres at 1 m depth; grows with depth squared (sensor noise)
    int min_inliers = 20;             // fewer inliers -> the alignment is not valid
    double min_inlier_fraction = 0.25;  // inliers / matches below this -> not valid
    unsigned random_seed = 7;         // RANSAC sampling seed (results are reproducible)
  };

  FeatureAligner();
  explicit FeatureAligner(const Options& options);
  const Options& options() const { return options_; }

  // Detects ORB features on frame->gray inside frame->feature_mask and keeps those with depth.
  // Idempotent (does nothing when frame->has_features). Thread safe for distinct frames.
  void extract(OdometryFrame* frame) const;

  // T_ref_cur from features of both frames (both must have been extracted; throws pf2::Error
  // otherwise). Thread safe.
  SparseAlignment align(const OdometryFrame& reference, const OdometryFrame& current) const;

 private:
  Options options_;
};

}  // namespace pf2
