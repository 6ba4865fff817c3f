#pragma once
// Body fitting (paper §III-C): the body model's pose, shape and root placement in the CAMERA frame
// from one person's 2D keypoints (COCO-17) and, when given, the person's depth points D_h^t; and
// eq. 4, the body's placement in the world. The paper ran VIBE and OpenPose on a GPU; this is an
// optimisation on the CPU (Ceres, automatic derivatives of the joints' forward kinematics). See
// docs/body.md, "Body fitting".
#include <array>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/body/body_model.h"
#include "pf2/body/body_surface_aligner.h"
#include "pf2/core/camera_intrinsics.h"

namespace ceres {
class CostFunction;
class Problem;
}  // namespace ceres

namespace pf2 {

constexpr int kCocoKeypointCount = 17;

// COCO-17 keypoint order: 0 nose, 1 left_eye, 2 right_eye, 3 left_ear, 4 right_ear, 5 left_shoulder,
// 6 right_shoulder, 7 left_elbow, 8 right_elbow, 9 left_wrist, 10 right_wrist, 11 left_hip,
// 12 right_hip, 13 left_knee, 14 right_knee, 15 left_ankle, 16 right_ankle.
extern const std::array<const char*, kCocoKeypointCount> kCocoKeypointNames;

// The one COCO <-> body-joint correspondence of the project (fitter and benchmark both use it).
struct CocoJointLink {
  int joint;      // body joint (SMPL order) the keypoint observes; -1 = not used
  double weight;  // weight of its reprojection term relative to the limb keypoints
  // Where the keypoint lies relative to the joint (m), in the frame of the bone ending at the
  // joint (the parent joint's frame; body axes in the rest pose: x left, y up, z forward).
  std::array<double, 3> offset;
  // How far behind the visible surface around the keypoint the keypoint's point lies (m): the depth
  // term's target is that surface's depth plus this.
  double depth_below_surface;
};
// nose -> head (1); eyes unused (the head joint sits behind them and they add no constraint the
// nose does not); ears -> head (0.5 each); shoulders, elbows, wrists, hips, knees, ankles -> the
// SMPL joint of the same name (1). Offsets and depths below the surface are MoveNet's keypoints
// against the body model's joints, measured on a pf2_synth sequence (median over 200 views each;
// docs/body.md "Where MoveNet's keypoints lie"): hips 2.6 cm up the pelvis, shoulders 1.8 cm,
// ankles 2.8 cm up the shin, ears 4.8 cm to the side of the head joint.
extern const std::array<CocoJointLink, kCocoKeypointCount> kCocoToBodyJoint;

// A keypoint in pixels with a confidence in [0, 1]; confidence 0 (or a non-finite value) = missing.
struct BodyKeypoint {
  double u = 0, v = 0, confidence = 0;
};

// What the fitter is given for one person in one frame.
struct BodyFitInput {
  std::array<BodyKeypoint, kCocoKeypointCount> keypoints;  // COCO-17 order
  // The person's depth points D_h^t back-projected into the camera frame (metres); empty = no
  // depth term (2D only, distance from the body's size). depthPointsFromImage makes them.
  std::vector<Eigen::Vector3d> points_c;
  // The world's up direction in the camera frame, unit; zero = unknown, then the body starts upright
  // in an upright camera (the paper's R_x(180°)). Known from T_w_c: up_c = R_w_c^T up_w.
  Eigen::Vector3d up_c = Eigen::Vector3d::Zero();
  // The same person's fit in the previous frame, moved into this frame's camera frame by the caller
  // when the camera moved (bodyToWorld with T_c_now_c_prev); when set, the fit starts from it
  // instead of the eq. 2 initialisation.
  const BodyParameters* previous = nullptr;
};

struct BodyFitResult {
  bool valid = false;
  std::string message;        // why the fit is invalid (empty when valid)
  BodyParameters parameters;  // camera frame: evaluate() gives the body in camera coordinates
  std::array<Eigen::Vector3d, kBodyJointCount> joints_c;  // the fitted 24 joints, camera frame
  double cost = 0;            // final Ceres cost (0.5 * sum of squared weighted residuals)
  double initial_cost = 0;    // cost at the initialisation
  int keypoints_used = 0;     // keypoints with a linked joint and confidence >= min_confidence
  int depth_keypoints = 0;    // of those, the ones with a depth measurement (depth term)
  int iterations = 0;         // solver iterations over all stages
  // m the surface alignment moved the body along its pelvis ray (+ = away from the camera);
  // 0 when it was off, had no points or did not trust them.
  double surface_shift = 0;
};

// Fits the body model to one person (engine; see the header comment). The model is held by
// reference and must outlive the fitter.
class BodyFitter {
 public:
  struct Options {
    // Keypoints below this confidence are missing.
    double min_confidence = 0.1;
    // Fewer usable keypoints than this, or neither both shoulders nor both hips = invalid, no fit.
    int min_keypoints = 5;
    // Reprojection term: residual = weight_2d * sqrt(confidence * link weight) * (pixel error).
    double weight_2d = 1.0;
    // Depth term: per keypoint with person points within depth_radius_px of it, the linked joint's
    // z should be the median depth there plus the joint's depth below the surface (a per-joint
    // table in the .cpp). Residual = weight_depth * Huber_depth_delta(error in metres), so with the
    // default 1 cm weighs like 1.5 px. 0 = no depth term.
    double weight_depth = 150.0;
    double depth_delta = 0.05;       // m, Huber threshold of the depth residual
    double depth_radius_px = 4.0;    // pixels around a keypoint whose points count
    // A left/right keypoint pair closer in the image than this (metres at their depth) is seen
    // from the side: the keypoint of the pair farther from the camera (in the pose being fitted)
    // is hidden behind the nearer and measures the nearer side's surface, so its depth term only
    // keeps it from coming in front of that surface. [0, 1] m; 0 = every depth term two-sided.
    double side_view_separation = 0.075;
    // A keypoint within this many pixels of an image edge, or beyond it, marks where the body
    // leaves the view (MoveNet puts a joint outside its input at the edge): its reprojection
    // residual across that edge is one-sided, the joint may project anywhere beyond the keypoint.
    // Without it, a leg cut by the image's bottom edge was bent to bring the ankle into the image
    // (pf2_slam on pf2_synth: ankles out of view 31-35 cm off their pelvis-relative truth, median;
    // 8 px: 25-27 cm). 16 was the best of 8 / 16 / 32 (docs/BENCHMARKS.md). [0, 100] px; 0 = only
    // keypoints beyond the image.
    double edge_band = 16.0;
    // Keypoints lie at their joint plus CocoJointLink::offset (true) or at the joint itself.
    bool keypoint_offsets = true;
    // Pose prior: quadratic on the axis-angle of joints 1..23 (radians) around a relaxed standing
    // pose (arms lowered; docs/body.md), residual = weight_pose * scale_j * (angle - relaxed),
    // scale_j 1 for limbs, 3 for spine/neck/collars/feet/hands (not seen by COCO keypoints).
    // Joint limits: knees and elbows only bend one way (a one-sided penalty weight_limits * angle
    // beyond the limit). 5 rather than 2: a leg outside the image is held near the relaxed pose
    // instead of bent wherever MoveNet's guesses at the border pull it (pf2_slam, repeatable runs,
    // MPJPE sums over nine pf2_synth sequences 876 -> 826 mm and over six held-out ones 649 -> 597
    // mm, track RMSE and identity switches no worse; 10: 825 mm but track RMSE 58.5 -> 63.3 cm).
    double weight_pose = 5.0;
    double weight_limits = 50.0;
    // Shape prior: residual = weight_shape * beta (betas have unit variance).
    double weight_shape = 5.0;
    bool fit_shape = true;           // false: shape stays at the initial (or previous) shape
    // Upright prior when the world's up is known (BodyFitInput::up_c): residual = weight_upright *
    // (body up - up_c), about weight_upright x the tilt in radians (10 degrees at 50 weighs like
    // 8.7 px of reprojection error). 0 = none.
    double weight_upright = 50.0;
    // After the solve, the body moves along the ray through its pelvis until its torso's surface
    // meets the person's depth points (BodySurfaceAligner; only with points_c), and is solved
    // again from there with the root's depth held: residual = weight_surface_depth x (t_z - the
    // aligned t_z), 1000 = 1 cm weighs like 10 px. The depth term alone reads a dozen keypoints'
    // surroundings, where a pixel of mask error reads the background (pf2_slam, repeatable runs,
    // nine pf2_synth sequences: track RMSE sum 59.9 -> 54.8 cm, MPJPE 781 -> 757 mm; six held-out
    // ones 45.1 -> 40.5 cm, 568 -> 553 mm; weight 3000 about the same). >= 0.
    bool surface_alignment = true;
    BodySurfaceAligner::Options surface;  // the aligner's own settings (cells, occlusion, trust)
    double weight_surface_depth = 1000.0;
    // Temporal term when `previous` is given: residual = weight_temporal * (pose - previous pose).
    double weight_temporal = 0.0;
    // Solver: stage 1 fits root rotation + translation on the torso, stage 2 everything.
    int stage1_iterations = 20;
    int max_iterations = 60;
    // Shape coefficients fitted (the first ones of the model; more than the model has count as 0).
    static constexpr int kShapeCount = 10;
  };

  BodyFitter(const BodyModel& model, const Options& options);
  explicit BodyFitter(const BodyModel& model) : BodyFitter(model, Options()) {}

  // Fits one person. Throws pf2::Error for invalid intrinsics or options; bad keypoints (too few,
  // NaN) give valid = false with a message. Thread safe (const; Ceres runs single threaded).
  BodyFitResult fit(const BodyFitInput& input, const CameraIntrinsics& intrinsics) const;

  // Posed joints of parameters (the same as model.evaluate(p).joints without skinning the mesh).
  std::array<Eigen::Vector3d, kBodyJointCount> posedJoints(const BodyParameters& parameters) const;
  // Where the fitter expects each COCO keypoint of a body with these parameters: its joint plus
  // the link's offset (Options::keypoint_offsets); NaN for keypoints without a joint. Project them
  // to make exact keypoints. Thread safe (const).
  std::array<Eigen::Vector3d, kCocoKeypointCount> keypointPoints(const BodyParameters& parameters) const;

  const Options& options() const { return options_; }

 private:
  // The steps of fit() (the .cpp says what each does); ceres types stay out of this header.
  struct Observations;
  struct Variables;
  struct Posed;
  Posed pose(const BodyParameters& parameters) const;
  Observations observe(const BodyFitInput& input, const CameraIntrinsics& K, BodyFitResult* result) const;
  bool warmStart(const BodyParameters& previous, Variables* x) const;
  void initialOrientation(const BodyFitInput& input, const Observations& seen, const CameraIntrinsics& K,
                          Variables* x) const;
  void initialPosition(const BodyFitInput& input, const Observations& seen, const CameraIntrinsics& K,
                       Variables* x) const;
  ceres::CostFunction* dataTerm(const BodyFitInput& input, const Observations& seen, const CameraIntrinsics& K,
                                bool torso_only) const;
  struct SolveOutcome;
  // hold_depth: stage 2 alone, with the root translation's z held there (alignToSurface).
  SolveOutcome solve(const BodyFitInput& input, const Observations& seen, const CameraIntrinsics& K, Variables* x,
                     BodyFitResult* result, const double* hold_depth = nullptr) const;
  SolveOutcome alignToSurface(const BodyFitInput& input, const Observations& seen, const CameraIntrinsics& K,
                              Variables* x, BodyFitResult* result) const;
  static void parametersOf(const Variables& x, BodyParameters* parameters);
  void addUprightPrior(const BodyFitInput& input, Variables* x, ceres::Problem* problem) const;
  void addPriors(const BodyFitInput& input, Variables* x, ceres::Problem* problem) const;

  const BodyModel& model_;
  Options options_;
  BodySurfaceAligner aligner_;
  // Rest joints are linear in the shape: J(beta) = rest_joints_ + joint_shapedirs_ * beta.
  Eigen::Matrix<double, 3 * kBodyJointCount, 1> rest_joints_;
  Eigen::Matrix<double, 3 * kBodyJointCount, Options::kShapeCount> joint_shapedirs_;
};

// The person's depth pixels (CV_32F metres, 0 = none; the person's area of a frame, `image` being
// the whole frame so that pixel coordinates stay) back-projected into the camera frame, every
// `stride`-th pixel in each direction. Throws pf2::Error for another image type. Thread safe.
std::vector<Eigen::Vector3d> depthPointsFromImage(const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                                                  int stride = 2);

// Eq. 4: T_w_h = [R_w_c R_x(180°) | p_w], the human frame F_h (at the waist, x as the camera's,
// y and z reversed) placed in the world by the camera's rotation and the person's centre p_w (eq. 3).
// Thread safe.
Eigen::Isometry3d humanToWorld(const Eigen::Isometry3d& T_w_c, const Eigen::Vector3d& p_w);

// The exact rigid move of camera-frame body parameters into the world: evaluate() of the result is
// T_w_c applied to evaluate() of body_c. Needs the body's rest pelvis (model.restJoints(shape)[0])
// because the root rotates about it. Thread safe.
BodyParameters bodyToWorld(const BodyParameters& body_c, const Eigen::Isometry3d& T_w_c,
                           const Eigen::Vector3d& rest_pelvis);

}  // namespace pf2
