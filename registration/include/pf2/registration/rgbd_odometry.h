#pragma once
// Frame-to-keyframe RGB-D odometry on human-free depth.
//
// Coarse: FeatureAligner (ORB + 3D-3D RANSAC) when asked for or when no good prior exists.
// Fine: dense Gauss-Newton over a 3-level pyramid minimising, for each sampled pixel of the current
// frame, a photometric residual I_ref(pi(T p_cur)) - I_cur(u) and a point-to-plane residual
// n_ref . (T p_cur - p_ref) under projective data association, each normalised by its noise
// (intensity sigma; depth noise growing with z^2) and weighted by Huber's M-estimator. Jacobians
// are analytic (left perturbation of T_ref_cur); the normal equations are accumulated in parallel
// stripes (cv::parallel_for_).
//
// Pixels with depth 0 (no measurement, removed people) never take part; a person mask passed to
// prepare() removes those pixels from depth and from feature extraction as well.
#include <memory>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/frame.h"
#include "pf2/registration/feature_aligner.h"
#include "pf2/registration/keyframe.h"
#include "pf2/registration/odometry_frame.h"

namespace pf2 {

// Quality of a dense alignment; `valid` is the verdict from the Options thresholds.
struct DenseAlignment {
  bool valid = false;
  Eigen::Isometry3d T_ref_cur = Eigen::Isometry3d::Identity();
  int sampled_points = 0;        // current-frame samples with depth at the finest level used
  int associated_points = 0;     // of those, projected onto reference pixels with depth
  int inlier_points = 0;         // of those, with a point-to-plane residual below inlier_distance
  double inlier_ratio = 0.0;     // inlier_points / sampled_points (overlap and consistency)
  double geometric_rmse = 0.0;   // metres, point-to-plane over the inliers
  double photometric_rmse = 0.0; // intensity [0,1] over the inliers
  double hessian_condition = 0.0;  // largest / smallest eigenvalue of the final 6x6 normal matrix
  int iterations = 0;            // Gauss-Newton iterations over all levels
  // Inliers per associated point: how well what the alignment associates fits (consistency, not
  // overlap); 0 when nothing was associated.
  double agreement() const { return associated_points > 0 ? double(inlier_points) / associated_points : 0.0; }
};

struct OdometryResult {
  bool valid = false;
  Eigen::Isometry3d T_ref_cur = Eigen::Isometry3d::Identity();
  bool used_features = false;  // the sparse stage ran
  SparseAlignment sparse;      // meaningful when used_features
  DenseAlignment dense;
};

// Published lens distortion (OpenCV k1, k2, p1, p2, k3) of the TUM RGB-D cameras; their images
// are not rectified, and on fr1 the corners move by tens of pixels.
inline const std::vector<double> kTumFreiburg1Distortion{0.2624, -0.9531, -0.0054, 0.0026, 1.1633};
inline const std::vector<double> kTumFreiburg2Distortion{0.2312, -0.7849, -0.0033, -0.0001, 0.9172};

class RgbdOdometry {
 public:
  struct Options {
    // Lens distortion of the (depth-registered) colour camera, OpenCV order k1 k2 p1 p2 k3;
    // empty = the images are rectified. Colour, depth and mask are undistorted in prepare() to
    // the same pinhole intrinsics, so stored keyframes hold rectified images.
    std::vector<double> distortion;
    int pyramid_levels = 3;        // levels, each half the size of the one above
    int finest_level = 0;          // the finest level iterated (1 = stop at 320x240: faster, coarser)
    int iterations_coarse = 12;    // Gauss-Newton iterations at the coarsest level
    int iterations_fine = 4;       // at the finest level; levels between interpolate
    int max_points_per_level = 12000;  // current-frame samples per level (a regular grid)
    double min_depth = 0.2;        // metres; closer depth is discarded
    double max_depth = 6.0;        // metres; farther depth is discarded (TUM depth gets noisy)
    int person_mask_dilation = 4;  // pixels added around a person mask before it is cut out
    double intensity_sigma = 0.04;   // expected photometric noise, intensity units [0,1]; with
                                     // min_intensity_sigma > 0 the upper bound of the measured one
    // The photometric noise is measured at every iteration (1.4826 x the median absolute residual
    // of the associated points, kept within [min_intensity_sigma, intensity_sigma]): a clean
    // sensor then gets a tight scale against which the pixels of a moving person are outliers,
    // a blurred one keeps a loose one. 0 = always intensity_sigma.
    double min_intensity_sigma = 0.01;
    double depth_sigma = 0.01;       // point-to-plane noise at 1 m depth, metres (grows with z^2)
    // Points nearer than this are weighted as if they lay at this depth (metres, [0, 10]; 0 = the
    // z^2 model all the way): the model's tiny noise close to the lens gave a person a metre away
    // 10-600 times the weight of the room behind them, so one the detector missed pulled the pose
    // with them (pf2_synth xyz, 5 people, seed 7: ATE 38 -> 24 mm; the shared real and synthetic
    // sequences unchanged within 0.1 mm; docs/BENCHMARKS.md, "More pf2_synth sequences").
    double depth_sigma_floor_depth = 1.0;
    double photometric_weight = 1.0; // relative weight of the photometric term (0 = ICP only)
    double huber_k = 1.345;          // Huber threshold on the normalised point-to-plane residuals
    // Huber threshold on the normalised photometric residuals. Wider than the geometric one: on
    // real cameras (Bonn, TUM) blur, rolling shutter and exposure spread the static scene's
    // photometric residuals far beyond their measured core (1.4826 x MAD), and pf2_slam tracks
    // those sequences better when such pixels keep more weight (docs/BENCHMARKS.md, "Tracking
    // with the learned detector"; one alignment alone does not show the gain, tracking against
    // keyframes does).
    double photometric_huber_k = 3.0;
    double max_depth_difference = 0.07;  // relative: |z_ref - z| > this * z is occlusion, no match
    double max_normal_depth_jump = 0.05;  // relative depth change per pixel step across which no
                                          // normal is taken (a depth edge, not a surface)
    double convergence_step = 2e-5;  // stop a level when the update is below this (m and rad)
    // Motion prior of estimate(): the guess is also a Gaussian prior on the pose with these
    // standard deviations, added to the normal equations (a MAP estimate). Where the static scene
    // constrains the pose (thousands of points) it hardly matters; where it does not (a wall and
    // little else once people are removed) it keeps the unconstrained directions at the guess
    // instead of letting Gauss-Newton run off. 0 = no prior.
    double prior_sigma_translation = 0.03;  // metres
    double prior_sigma_rotation = 0.03;     // radians
    // Verdict thresholds:
    double inlier_distance = 0.03;   // metres, point-to-plane residual counted as inlier
    int min_inliers = 800;           // at the finest level used (after sampling)
    double min_inlier_ratio = 0.35;  // inlier_points / sampled_points
    double max_condition = 1e7;      // larger Hessian condition -> degenerate geometry, not valid
    double max_motion_from_prior = 0.3;  // metres; dense result farther from its start is rejected
    // When the sparse stage runs: always (robust, costs ~5 ms) or only when the dense alignment
    // from the prior is not valid.
    bool features_every_frame = false;
    FeatureAligner::Options features;
  };

  RgbdOdometry();
  explicit RgbdOdometry(const Options& options);
  const Options& options() const { return options_; }
  const FeatureAligner& featureAligner() const { return features_; }

  // Pyramids of a frame. person_mask: empty, or CV_8U of the frame's size, 255 = person. Throws
  // pf2::Error on images of wrong type or size. Thread safe.
  OdometryFrame prepare(const Frame& frame, const cv::Mat& person_mask = cv::Mat()) const;
  // Pyramids of a stored keyframe (its grey image and depth), features copied, made a reference.
  // Thread safe.
  OdometryFrame prepare(const Keyframe& keyframe) const;
  // Adds gradients, normals and features so the frame can be a reference (keyframe).
  // Idempotent. Thread safe for distinct frames.
  void makeReference(OdometryFrame* frame) const;

  // Dense refinement from T_ref_cur_guess; a non-null T_ref_cur_prior adds the motion prior
  // (Options::prior_sigma_*). The reference must have been made a reference. Thread safe.
  DenseAlignment refine(const OdometryFrame& reference, const OdometryFrame& current,
                        const Eigen::Isometry3d& T_ref_cur_guess,
                        const Eigen::Isometry3d* T_ref_cur_prior = nullptr) const;

  // Sparse (per Options) + dense, T_ref_cur_guess being the motion prior of the dense stage. The
  // reference must have been made a reference (throws
  // pf2::Error otherwise); the current frame's features are extracted on demand. Thread safe for
  // distinct current frames.
  OdometryResult estimate(const OdometryFrame& reference, OdometryFrame* current,
                          const Eigen::Isometry3d& T_ref_cur_guess) const;
  // Sparse first, then dense from its pose (no prior: relocalisation, loop verification).
  OdometryResult estimateWithoutPrior(const OdometryFrame& reference, OdometryFrame* current) const;

 private:
  OdometryFrame prepareGray(const cv::Mat& gray, const cv::Mat& depth_m,
                            const CameraIntrinsics& intrinsics, double timestamp, int index,
                            const cv::Mat& person_mask) const;

  struct UndistortMaps;  // lazily built remap tables for the frame size, shared by copies

  Options options_;
  FeatureAligner features_;
  std::shared_ptr<UndistortMaps> undistort_;
};

}  // namespace pf2
