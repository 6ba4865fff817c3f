#include "pf2/body/body_fitter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include <ceres/ceres.h>
#include <ceres/rotation.h>
#include <opencv2/core.hpp>

#include "pf2/core/error.h"
#include "pf2/core/median.h"

namespace pf2 {

const std::array<const char*, kCocoKeypointCount> kCocoKeypointNames = {
    "nose",       "left_eye",   "right_eye",      "left_ear",       "right_ear",  "left_shoulder",
    "right_shoulder", "left_elbow", "right_elbow", "left_wrist",    "right_wrist", "left_hip",
    "right_hip",  "left_knee",  "right_knee",     "left_ankle",     "right_ankle"};

const std::array<CocoJointLink, kCocoKeypointCount> kCocoToBodyJoint = {{
    {15, 1.0, {0.0, 0.008, 0.0}, 0.085},       // nose -> head
    {-1, 0.0, {0.0, 0.0, 0.0}, 0.0},           // left_eye
    {-1, 0.0, {0.0, 0.0, 0.0}, 0.0},           // right_eye
    {15, 0.5, {0.048, 0.018, 0.0}, 0.06},      // left_ear -> head
    {15, 0.5, {-0.048, 0.018, 0.0}, 0.06},     // right_ear -> head
    {16, 1.0, {0.0, 0.018, 0.0}, 0.045},       // left_shoulder
    {17, 1.0, {0.0, 0.018, 0.0}, 0.045},       // right_shoulder
    {18, 1.0, {-0.012, 0.0, 0.0}, 0.03},       // left_elbow
    {19, 1.0, {0.012, 0.0, 0.0}, 0.03},        // right_elbow
    {20, 1.0, {0.0, 0.0, 0.0}, 0.015},         // left_wrist
    {21, 1.0, {0.0, 0.0, 0.0}, 0.015},         // right_wrist
    {1, 1.0, {0.0, 0.026, 0.0}, 0.12},         // left_hip
    {2, 1.0, {0.0, 0.026, 0.0}, 0.12},         // right_hip
    {4, 1.0, {0.0, 0.0, 0.0}, 0.05},           // left_knee
    {5, 1.0, {0.0, 0.0, 0.0}, 0.05},           // right_knee
    {7, 1.0, {0.0, 0.028, 0.0}, 0.03},         // left_ankle
    {8, 1.0, {0.0, 0.028, 0.0}, 0.03},         // right_ankle
}};

namespace {

constexpr int kShapes = BodyFitter::Options::kShapeCount;
constexpr int kBodyPoseSize = 3 * (kBodyJointCount - 1);  // joints 1..23
constexpr int kResiduals2d = 2 * kCocoKeypointCount;
constexpr int kResidualsData = kResiduals2d + kCocoKeypointCount;  // 2D + depth per keypoint

// The pose the prior pulls towards and the fit starts from: standing, arms lowered 70° from the
// T pose (zero pose would hold the arms straight out, which people rarely do).
std::array<Eigen::Vector3d, kBodyJointCount> relaxedPose() {
  std::array<Eigen::Vector3d, kBodyJointCount> pose;
  for (auto& p : pose) p.setZero();
  pose[16] = {0, 0, -1.2};  // left shoulder: the arm lowers with -z
  pose[17] = {0, 0, 1.2};   // right shoulder: +z
  return pose;
}

// Posed joints from (root axis-angle, translation, 23 joint axis-angles, shapes), as
// BodyModel::evaluate computes them: G_j = G_parent * [R_j | J_j - J_parent], joint = G_j.t + t.
// G_R receives each joint's rotation in the output frame, row-major.
template <typename T>
void forwardKinematics(const Eigen::Matrix<double, 3 * kBodyJointCount, 1>& rest,
                       const Eigen::Matrix<double, 3 * kBodyJointCount, kShapes>& shapedirs, const T* root,
                       const T* translation, const T* body, const T* shape, T joints[kBodyJointCount][3],
                       T G_R[kBodyJointCount][9]) {
  T J[kBodyJointCount][3];
  for (int i = 0; i < 3 * kBodyJointCount; ++i) {
    T value = T(rest[i]);
    for (int b = 0; b < kShapes; ++b) value += shapedirs(i, b) * shape[b];
    J[i / 3][i % 3] = value;
  }
  for (int j = 0; j < kBodyJointCount; ++j) {
    T R[9];
    ceres::AngleAxisToRotationMatrix(j == 0 ? root : body + 3 * (j - 1), ceres::RowMajorAdapter3x3(R));
    const int parent = kBodyJointParents[j];
    if (parent < 0) {
      std::copy(R, R + 9, G_R[j]);
      for (int k = 0; k < 3; ++k) joints[j][k] = J[j][k];
      continue;
    }
    const T* P = G_R[parent];
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) G_R[j][3 * r + c] = P[3 * r] * R[c] + P[3 * r + 1] * R[3 + c] + P[3 * r + 2] * R[6 + c];
      joints[j][r] = joints[parent][r] + P[3 * r] * (J[j][0] - J[parent][0]) +
                     P[3 * r + 1] * (J[j][1] - J[parent][1]) + P[3 * r + 2] * (J[j][2] - J[parent][2]);
    }
  }
  for (int j = 0; j < kBodyJointCount; ++j) {
    for (int k = 0; k < 3; ++k) joints[j][k] += translation[k];
  }
}

// Where a keypoint lies on the posed body: its joint plus the link's offset, which turns with the
// bone that ends at the joint (the parent's rotation).
template <typename T>
void keypointPoint(const T joints[kBodyJointCount][3], const T G_R[kBodyJointCount][9], int joint,
                   const std::array<double, 3>& offset, T point[3]) {
  const T* R = G_R[std::max(0, kBodyJointParents[joint])];
  for (int r = 0; r < 3; ++r) {
    point[r] = joints[joint][r] + R[3 * r] * offset[0] + R[3 * r + 1] * offset[1] + R[3 * r + 2] * offset[2];
  }
}

// The data terms: reprojection of each linked keypoint (2 residuals) and its depth (1 residual),
// computed from one forward kinematics per evaluation. Unused keypoints have weight 0.
struct DataTerm {
  struct Keypoint {
    int joint = -1;
    std::array<double, 3> offset{};  // the keypoint relative to the joint (CocoJointLink::offset)
    double u = 0, v = 0;
    double weight_2d = 0;     // 0 = not used
    double depth = 0;         // target z of the keypoint's point (surface + depth below it); if weight_depth > 0
    double weight_depth = 0;
    // The other keypoint of a left/right pair seen from the side (-1: none): of the two, the one
    // farther from the camera in the current pose hides behind the nearer, its measured surface
    // is the nearer's, and its depth term only keeps it from coming in front of that surface.
    int hidden_partner = -1;
    // A keypoint at an image edge marks where the body leaves the view: the joint may lie anywhere
    // beyond that edge, so its residual across the edge is one-sided (flags: kBeyond*).
    int beyond = 0;
  };
  static constexpr int kBeyondLeft = 1, kBeyondRight = 2, kBeyondTop = 4, kBeyondBottom = 8;
  const Eigen::Matrix<double, 3 * kBodyJointCount, 1>* rest;
  const Eigen::Matrix<double, 3 * kBodyJointCount, kShapes>* shapedirs;
  std::array<Keypoint, kCocoKeypointCount> keypoints;
  double fx, fy, cx, cy, depth_delta;

  template <typename T>
  bool operator()(const T* root, const T* translation, const T* body, const T* shape, T* residuals) const {
    using std::abs;
    using std::sqrt;
    T joints[kBodyJointCount][3];
    T G_R[kBodyJointCount][9];
    forwardKinematics(*rest, *shapedirs, root, translation, body, shape, joints, G_R);
    T points[kCocoKeypointCount][3];
    for (int k = 0; k < kCocoKeypointCount; ++k) {
      if (keypoints[k].joint >= 0) keypointPoint(joints, G_R, keypoints[k].joint, keypoints[k].offset, points[k]);
    }
    for (int k = 0; k < kCocoKeypointCount; ++k) {
      const Keypoint& kp = keypoints[k];
      residuals[2 * k] = residuals[2 * k + 1] = residuals[kResiduals2d + k] = T(0);
      if (kp.joint < 0) continue;
      const T* p = points[k];
      if (kp.weight_2d > 0) {
        // A joint behind or at the camera would divide by ~0: clamp its depth; the other terms
        // bring it back in front.
        const T z = p[2] < T(0.05) ? T(0.05) : p[2];
        T du = fx * p[0] / z + cx - kp.u, dv = fy * p[1] / z + cy - kp.v;
        if (((kp.beyond & kBeyondLeft) && du < T(0)) || ((kp.beyond & kBeyondRight) && du > T(0))) du = T(0);
        if (((kp.beyond & kBeyondTop) && dv < T(0)) || ((kp.beyond & kBeyondBottom) && dv > T(0))) dv = T(0);
        residuals[2 * k] = kp.weight_2d * du;
        residuals[2 * k + 1] = kp.weight_2d * dv;
      }
      if (kp.weight_depth > 0) {
        // Huber as a residual: 0.5 r^2 equals the Huber loss of the error e. The hidden one of a
        // pair seen from the side may lie any distance behind its target.
        T e = p[2] - kp.depth;
        if (kp.hidden_partner >= 0 && p[2] > points[kp.hidden_partner][2] && e > T(0)) e = T(0);
        const T r = abs(e) <= T(depth_delta) ? e
                                             : (e > T(0) ? T(1) : T(-1)) * sqrt(2.0 * depth_delta * abs(e) -
                                                                               depth_delta * depth_delta);
        residuals[kResiduals2d + k] = kp.weight_depth * r;
      }
    }
    return true;
  }
};

// Left/right keypoint pairs (ears, shoulders, elbows, wrists, hips, knees, ankles) whose two
// keypoints lie closer in the image than side_view_separation at their depth: a person seen from
// the side. The keypoint on the far side then falls on the near side's surface, and a two-sided
// depth term would pull its joint forward by the body's width.
void pairSideViews(const BodyFitInput& input, const std::array<double, kCocoKeypointCount>& surface,
                   const CameraIntrinsics& K, double side_view_separation, DataTerm* term) {
  for (int left = 3; left + 1 < kCocoKeypointCount; left += 2) {
    const int right = left + 1;
    if (term->keypoints[left].weight_depth <= 0 || term->keypoints[right].weight_depth <= 0) continue;
    const double du = input.keypoints[left].u - input.keypoints[right].u;
    const double dv = input.keypoints[left].v - input.keypoints[right].v;
    const double depth = 0.5 * (surface[left] + surface[right]);
    if (std::sqrt(du * du + dv * dv) * depth >= K.fx * side_view_separation) continue;
    term->keypoints[left].hidden_partner = right;
    term->keypoints[right].hidden_partner = left;
  }
}

// Pose prior around the relaxed pose with per-joint scales, plus one-sided joint limits.
constexpr int kLimitResiduals = 4;
struct PosePrior {
  std::array<double, kBodyPoseSize> mean;
  std::array<double, kBodyPoseSize> scale;
  double weight_limits;

  template <typename T>
  bool operator()(const T* body, T* residuals) const {
    for (int i = 0; i < kBodyPoseSize; ++i) residuals[i] = scale[i] * (body[i] - mean[i]);
    // Knees flex with +x only; the left elbow with -y, the right one with +y (forearm forward).
    auto beyond = [](const T& excess) { return excess > T(0) ? excess : T(0); };
    const T* left_knee = body + 3 * (4 - 1);
    const T* right_knee = body + 3 * (5 - 1);
    const T* left_elbow = body + 3 * (18 - 1);
    const T* right_elbow = body + 3 * (19 - 1);
    residuals[kBodyPoseSize + 0] = weight_limits * beyond(-left_knee[0]);
    residuals[kBodyPoseSize + 1] = weight_limits * beyond(-right_knee[0]);
    residuals[kBodyPoseSize + 2] = weight_limits * beyond(left_elbow[1]);
    residuals[kBodyPoseSize + 3] = weight_limits * beyond(-right_elbow[1]);
    return true;
  }
};

// The body's up axis (the root's y, the rest spine's direction) along the world's up seen from the
// camera: residual = weight * (R_root e_y - up_c), whose norm is 2 sin(tilt / 2), about the tilt
// in radians.
struct UprightPrior {
  Eigen::Vector3d up_c;
  double weight;
  template <typename T>
  bool operator()(const T* root, T* residuals) const {
    const T body_up[3] = {T(0), T(1), T(0)};
    T up[3];
    ceres::AngleAxisRotatePoint(root, body_up, up);
    for (int k = 0; k < 3; ++k) residuals[k] = weight * (up[k] - T(up_c[k]));
    return true;
  }
};

// The root translation's depth held where the surface alignment put it (the re-solve after it).
struct DepthHold {
  double depth;
  double weight;
  template <typename T>
  bool operator()(const T* translation, T* residual) const {
    residual[0] = weight * (translation[2] - T(depth));
    return true;
  }
};

struct ShapePrior {
  double weight;
  template <typename T>
  bool operator()(const T* shape, T* residuals) const {
    for (int b = 0; b < kShapes; ++b) residuals[b] = weight * shape[b];
    return true;
  }
};

struct TemporalTerm {
  std::array<double, kBodyPoseSize> previous;
  double weight;
  template <typename T>
  bool operator()(const T* body, T* residuals) const {
    for (int i = 0; i < kBodyPoseSize; ++i) residuals[i] = weight * (body[i] - previous[i]);
    return true;
  }
};

bool usable(const BodyKeypoint& kp, double min_confidence) {
  return std::isfinite(kp.u) && std::isfinite(kp.v) && std::isfinite(kp.confidence) &&
         kp.confidence >= min_confidence;
}

// Rotation from the body frame (y up, facing +z, left +x) to the camera frame for a body standing
// along up_c and facing `forward_c` (made orthogonal to up_c).
Eigen::Matrix3d bodyRotation(const Eigen::Vector3d& up_c, const Eigen::Vector3d& forward_c) {
  Eigen::Vector3d forward = forward_c - forward_c.dot(up_c) * up_c;
  if (forward.norm() < 1e-6) forward = Eigen::Vector3d::UnitZ().cross(up_c);  // looking straight down
  forward.normalize();
  Eigen::Matrix3d R;
  R.col(0) = up_c.cross(forward);  // left = up x forward
  R.col(1) = up_c;
  R.col(2) = forward;
  return R;
}

}  // namespace

BodyFitter::BodyFitter(const BodyModel& model, const Options& options)
    : model_(model), options_(options), aligner_(model, options.surface) {
  const auto rest = model.restJoints(Eigen::VectorXd::Zero(kShapes));
  for (int j = 0; j < kBodyJointCount; ++j) rest_joints_.segment<3>(3 * j) = rest[j];
  for (int b = 0; b < kShapes; ++b) {
    const auto moved = model.restJoints(Eigen::VectorXd::Unit(kShapes, b));
    for (int j = 0; j < kBodyJointCount; ++j) joint_shapedirs_.block<3, 1>(3 * j, b) = moved[j] - rest[j];
  }
  const bool ok = options.min_confidence >= 0 && options.min_keypoints >= 1 && options.weight_2d > 0 &&
                  options.weight_depth >= 0 && options.depth_delta > 0 && options.depth_radius_px > 0 &&
                  options.weight_pose >= 0 && options.weight_limits >= 0 && options.weight_shape >= 0 &&
                  options.weight_temporal >= 0 && options.weight_upright >= 0 && options.weight_surface_depth >= 0 &&
                  options.stage1_iterations >= 0 && options.max_iterations >= 1 &&
                  options.side_view_separation >= 0 && options.side_view_separation <= 1 &&
                  options.edge_band >= 0 && options.edge_band <= 100;
  if (!ok) {
    throw Error(
        "BodyFitter: an option is out of range (weights >= 0, iterations >= 1, radius > 0, side_view_separation in "
        "[0, 1] m, edge_band in [0, 100] px)");
  }
}

// The posed joints and each joint's rotation (row-major) for parameters, by the fitter's kinematics.
struct BodyFitter::Posed {
  double joints[kBodyJointCount][3];
  double rotations[kBodyJointCount][9];
};

BodyFitter::Posed BodyFitter::pose(const BodyParameters& parameters) const {
  std::array<double, kBodyPoseSize> body;
  for (int j = 1; j < kBodyJointCount; ++j) {
    for (int k = 0; k < 3; ++k) body[3 * (j - 1) + k] = parameters.pose[j][k];
  }
  std::array<double, kShapes> shape{};
  for (int b = 0; b < std::min<int>(kShapes, parameters.shape.size()); ++b) shape[b] = parameters.shape[b];
  Posed posed;
  forwardKinematics(rest_joints_, joint_shapedirs_, parameters.pose[0].data(), parameters.translation.data(),
                    body.data(), shape.data(), posed.joints, posed.rotations);
  return posed;
}

std::array<Eigen::Vector3d, kBodyJointCount> BodyFitter::posedJoints(const BodyParameters& parameters) const {
  const Posed posed = pose(parameters);
  std::array<Eigen::Vector3d, kBodyJointCount> out;
  for (int j = 0; j < kBodyJointCount; ++j) out[j] = {posed.joints[j][0], posed.joints[j][1], posed.joints[j][2]};
  return out;
}

std::array<Eigen::Vector3d, kCocoKeypointCount> BodyFitter::keypointPoints(const BodyParameters& parameters) const {
  const Posed posed = pose(parameters);
  std::array<Eigen::Vector3d, kCocoKeypointCount> out;
  for (int k = 0; k < kCocoKeypointCount; ++k) {
    const CocoJointLink& link = kCocoToBodyJoint[k];
    out[k].setConstant(std::numeric_limits<double>::quiet_NaN());
    if (link.joint < 0) continue;
    const std::array<double, 3> none{};
    keypointPoint(posed.joints, posed.rotations, link.joint, options_.keypoint_offsets ? link.offset : none,
                  out[k].data());
  }
  return out;
}

// What fit() works from: the usable keypoints, the person's mean depth (eq. 2's d_m) and the
// surface depth around each keypoint (0 = none).
struct BodyFitter::Observations {
  std::array<bool, kCocoKeypointCount> use{};
  bool shoulders = false, hips = false;
  double mean_depth = 0;
  std::array<double, kCocoKeypointCount> surface{};
};

// How the last solver stage ended.
struct BodyFitter::SolveOutcome {
  bool failed = false;  // Ceres reported FAILURE
  std::string message;  // Ceres' summary message
};

// The solver's parameter blocks: root axis-angle, translation, joints 1..23, shape.
struct BodyFitter::Variables {
  std::array<double, 3> root{};
  std::array<double, 3> translation{};
  std::array<double, kBodyPoseSize> body{};
  std::array<double, kShapes> shape{};
};

namespace {

// The relaxed pose of joints 1..23 as one parameter block (the initial pose and the pose prior's
// mean), computed once.
const std::array<double, kBodyPoseSize>& relaxedBody() {
  static const std::array<double, kBodyPoseSize> body = [] {
    const std::array<Eigen::Vector3d, kBodyJointCount> relaxed = relaxedPose();
    std::array<double, kBodyPoseSize> b{};
    for (int j = 1; j < kBodyJointCount; ++j) {
      for (int k = 0; k < 3; ++k) b[3 * (j - 1) + k] = relaxed[j][k];
    }
    return b;
  }();
  return body;
}

}  // namespace

BodyFitResult BodyFitter::fit(const BodyFitInput& input, const CameraIntrinsics& K) const {
  if (!(std::isfinite(K.fx) && std::isfinite(K.fy) && std::isfinite(K.cx) && std::isfinite(K.cy) && K.fx > 0 &&
        K.fy > 0)) {
    throw Error("BodyFitter: invalid intrinsics (focal lengths must be finite and positive)");
  }
  BodyFitResult result;
  for (auto& j : result.joints_c) j.setZero();
  const Observations seen = observe(input, K, &result);
  if (result.keypoints_used < options_.min_keypoints) {
    result.message = "too few keypoints (" + std::to_string(result.keypoints_used) + " usable, need " +
                     std::to_string(options_.min_keypoints) + ")";
    return result;
  }
  if (!(seen.shoulders || seen.hips)) {
    result.message = "neither both shoulders nor both hips seen: nothing to place the body by";
    return result;
  }
  Variables x;
  if (input.previous != nullptr) {
    if (!warmStart(*input.previous, &x)) {
      result.message = "previous fit is not finite";
      return result;
    }
  } else {
    x.body = relaxedBody();
    initialOrientation(input, seen, K, &x);
    initialPosition(input, seen, K, &x);
  }
  SolveOutcome outcome = solve(input, seen, K, &x, &result);
  parametersOf(x, &result.parameters);
  if (options_.surface_alignment && !input.points_c.empty() && !outcome.failed) {
    outcome = alignToSurface(input, seen, K, &x, &result);
  }
  result.joints_c = posedJoints(result.parameters);
  bool finite = std::isfinite(result.cost);
  for (const auto& j : result.joints_c) finite = finite && j.allFinite();
  if (outcome.failed || !finite) {
    result.message = "solver failed: " + outcome.message;
    return result;
  }
  result.valid = true;
  return result;
}

void BodyFitter::parametersOf(const Variables& x, BodyParameters* parameters) {
  for (int k = 0; k < 3; ++k) parameters->pose[0][k] = x.root[k], parameters->translation[k] = x.translation[k];
  for (int j = 1; j < kBodyJointCount; ++j) {
    for (int k = 0; k < 3; ++k) parameters->pose[j][k] = x.body[3 * (j - 1) + k];
  }
  parameters->shape = Eigen::Map<const Eigen::VectorXd>(x.shape.data(), kShapes);
}

// The fit moved along its pelvis ray onto the person's measured torso surface (BodySurfaceAligner),
// then solved again from there with its depth held (DepthHold): the limbs follow their keypoints
// from the new place instead of keeping the depth offset of the old one. Returns how the last solve
// ended; the fit stays as it was when the aligner does not trust the person's points.
BodyFitter::SolveOutcome BodyFitter::alignToSurface(const BodyFitInput& input, const Observations& seen,
                                                    const CameraIntrinsics& K, Variables* x,
                                                    BodyFitResult* result) const {
  BodyParameters aligned = result->parameters;
  const BodySurfaceAligner::Result moved = aligner_.align(input.points_c, K, &aligned);
  if (!moved.applied) return {};
  result->surface_shift = moved.shift;
  for (int k = 0; k < 3; ++k) x->translation[k] = aligned.translation[k];
  const double depth = aligned.translation.z();
  const SolveOutcome outcome = solve(input, seen, K, x, result, &depth);
  parametersOf(*x, &result->parameters);
  return outcome;
}

// The usable keypoints and the person's depth: mean depth (eq. 2's d_m) and the median depth of
// the points within depth_radius_px of each keypoint. Counts keypoints_used and depth_keypoints.
BodyFitter::Observations BodyFitter::observe(const BodyFitInput& input, const CameraIntrinsics& K,
                                             BodyFitResult* result) const {
  Observations seen;
  for (int k = 0; k < kCocoKeypointCount; ++k) {
    seen.use[k] = kCocoToBodyJoint[k].joint >= 0 && usable(input.keypoints[k], options_.min_confidence);
    result->keypoints_used += seen.use[k];
  }
  seen.shoulders = seen.use[5] && seen.use[6];
  seen.hips = seen.use[11] && seen.use[12];
  std::vector<Eigen::Vector3d> points;
  points.reserve(input.points_c.size());
  double depth_sum = 0;
  for (const Eigen::Vector3d& p : input.points_c) {
    if (p.allFinite() && p.z() > 0) {
      points.push_back(p);
      depth_sum += p.z();
    }
  }
  seen.mean_depth = points.empty() ? 0.0 : depth_sum / points.size();
  if (!(options_.weight_depth > 0) || points.empty()) return seen;
  std::array<std::vector<double>, kCocoKeypointCount> near;
  const double r2 = options_.depth_radius_px * options_.depth_radius_px;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector2d px = K.project(p);
    for (int k = 0; k < kCocoKeypointCount; ++k) {
      if (!seen.use[k]) continue;
      const double du = px.x() - input.keypoints[k].u, dv = px.y() - input.keypoints[k].v;
      if (du * du + dv * dv <= r2) near[k].push_back(p.z());
    }
  }
  for (int k = 0; k < kCocoKeypointCount; ++k) {
    if (!near[k].empty()) {
      seen.surface[k] = upperMedian(&near[k]);
      ++result->depth_keypoints;
    }
  }
  return seen;
}

// Temporal warm start: the previous fit as it was. False when it is not finite.
bool BodyFitter::warmStart(const BodyParameters& prev, Variables* x) const {
  for (int k = 0; k < 3; ++k) x->root[k] = prev.pose[0][k], x->translation[k] = prev.translation[k];
  for (int j = 1; j < kBodyJointCount; ++j) {
    for (int k = 0; k < 3; ++k) x->body[3 * (j - 1) + k] = prev.pose[j][k];
  }
  for (int b = 0; b < std::min<int>(kShapes, prev.shape.size()); ++b) x->shape[b] = prev.shape[b];
  bool finite = true;
  for (double v : x->root) finite = finite && std::isfinite(v);
  for (double v : x->translation) finite = finite && std::isfinite(v);
  for (double v : x->body) finite = finite && std::isfinite(v);
  for (double v : x->shape) finite = finite && std::isfinite(v);
  return finite;
}

// Orientation: upright along up_c (the paper's R_x(180°) when unknown), facing the camera or away
// from it depending on which side the person's left keypoints appear. With depth at both
// shoulders or both hips, the lifted left-right vector gives the yaw itself.
void BodyFitter::initialOrientation(const BodyFitInput& input, const Observations& seen, const CameraIntrinsics& K,
                                    Variables* x) const {
  const auto& kp = input.keypoints;
  Eigen::Vector3d up_c = input.up_c;
  up_c = up_c.allFinite() && up_c.norm() > 1e-6 ? Eigen::Vector3d(up_c.normalized()) : Eigen::Vector3d(0, -1, 0);
  Eigen::Vector3d across_c = Eigen::Vector3d::Zero();  // right -> left, camera frame
  double left_minus_right_u = 0;
  for (const auto& [l, r] : {std::pair<int, int>{5, 6}, std::pair<int, int>{11, 12}}) {
    if (!(seen.use[l] && seen.use[r])) continue;
    left_minus_right_u += kp[l].u - kp[r].u;
    if (seen.surface[l] > 0 && seen.surface[r] > 0) {
      across_c += K.backProject(kp[l].u, kp[l].v, seen.surface[l]) - K.backProject(kp[r].u, kp[r].v, seen.surface[r]);
    }
  }
  // Facing the camera, the body's left (+x) appears on the image's right.
  const Eigen::Vector3d toward_camera(0, 0, -1);
  Eigen::Vector3d forward_c = left_minus_right_u >= 0 ? toward_camera : Eigen::Vector3d(-toward_camera);
  across_c -= across_c.dot(up_c) * up_c;
  if (across_c.norm() > 0.1) forward_c = across_c.normalized().cross(up_c);  // forward = left x up
  const Eigen::AngleAxisd aa(bodyRotation(up_c, forward_c));
  const Eigen::Vector3d root_aa = aa.angle() * aa.axis();
  for (int k = 0; k < 3; ++k) x->root[k] = root_aa[k];
}

// Position (eq. 2): the pelvis at the hips' midpoint (else the centre of the keypoints' box) at the
// mean depth d_m of the person's points plus the pelvis' depth below the surface. Without depth,
// the distance at which the body's rest torso (shoulders to hips) has the length seen in the image.
void BodyFitter::initialPosition(const BodyFitInput& input, const Observations& seen, const CameraIntrinsics& K,
                                 Variables* x) const {
  const auto& kp = input.keypoints;
  double u0 = 1e300, v0 = 1e300, u1 = -1e300, v1 = -1e300;
  for (int k = 0; k < kCocoKeypointCount; ++k) {
    if (!seen.use[k]) continue;
    u0 = std::min(u0, kp[k].u), u1 = std::max(u1, kp[k].u);
    v0 = std::min(v0, kp[k].v), v1 = std::max(v1, kp[k].v);
  }
  const Eigen::Vector2d pelvis_px = seen.hips ? Eigen::Vector2d(0.5 * (kp[11].u + kp[12].u), 0.5 * (kp[11].v + kp[12].v))
                                              : Eigen::Vector2d(0.5 * (u0 + u1), 0.5 * (v0 + v1));
  double z = seen.mean_depth > 0 ? seen.mean_depth + kCocoToBodyJoint[11].depth_below_surface : 0.0;
  if (z <= 0) {
    const Eigen::Vector3d rest_torso = 0.5 * (rest_joints_.segment<3>(3 * 16) + rest_joints_.segment<3>(3 * 17)) -
                                       0.5 * (rest_joints_.segment<3>(3 * 1) + rest_joints_.segment<3>(3 * 2));
    if (seen.shoulders && seen.hips) {
      const double torso_px = std::hypot(0.5 * (kp[5].u + kp[6].u - kp[11].u - kp[12].u),
                                         0.5 * (kp[5].v + kp[6].v - kp[11].v - kp[12].v));
      z = K.fy * rest_torso.norm() / std::max(torso_px, 1.0);
    } else {
      // One pair only: its width against the body's rest width.
      const int l = seen.shoulders ? 5 : 11, r = seen.shoulders ? 6 : 12;
      const double width = (rest_joints_.segment<3>(3 * kCocoToBodyJoint[l].joint) -
                            rest_joints_.segment<3>(3 * kCocoToBodyJoint[r].joint)).norm();
      z = K.fx * width / std::max(std::hypot(kp[l].u - kp[r].u, kp[l].v - kp[r].v), 1.0);
    }
    z = std::min(std::max(z, 0.3), 20.0);
  }
  const Eigen::Vector3d pelvis_c = K.backProject(pelvis_px.x(), pelvis_px.y(), z);
  for (int k = 0; k < 3; ++k) x->translation[k] = pelvis_c[k] - rest_joints_[k];
}

namespace {

// The image edges a keypoint at (u, v) lies within `band` pixels of, or beyond (DataTerm::kBeyond*
// flags): MoveNet puts a joint outside its input at the input's edge, so such a keypoint only says
// that the joint lies at or beyond that edge. With band 0 only keypoints beyond the image are flagged.
int edgesBeyond(double u, double v, const CameraIntrinsics& K, double band) {
  int flags = 0;
  if (u < band) flags |= DataTerm::kBeyondLeft;
  if (u > K.width - 1 - band) flags |= DataTerm::kBeyondRight;
  if (v < band) flags |= DataTerm::kBeyondTop;
  if (v > K.height - 1 - band) flags |= DataTerm::kBeyondBottom;
  return flags;
}

}  // namespace

// The data term with this person's keypoints; `torso_only` keeps head, shoulders and hips (the
// first stage, where arms and legs are still at their initial pose).
ceres::CostFunction* BodyFitter::dataTerm(const BodyFitInput& input, const Observations& seen, const CameraIntrinsics& K,
                                          bool torso_only) const {
  auto* term = new DataTerm{&rest_joints_, &joint_shapedirs_, {}, K.fx, K.fy, K.cx, K.cy, options_.depth_delta};
  for (int k = 0; k < kCocoKeypointCount; ++k) {
    if (!seen.use[k]) continue;
    const int joint = kCocoToBodyJoint[k].joint;
    if (torso_only && !(joint == 15 || joint == 16 || joint == 17 || joint == 1 || joint == 2)) continue;
    DataTerm::Keypoint& t = term->keypoints[k];
    t.joint = joint;
    if (options_.keypoint_offsets) t.offset = kCocoToBodyJoint[k].offset;
    t.u = input.keypoints[k].u;
    t.v = input.keypoints[k].v;
    t.weight_2d = options_.weight_2d * std::sqrt(std::min(1.0, input.keypoints[k].confidence) * kCocoToBodyJoint[k].weight);
    t.beyond = edgesBeyond(t.u, t.v, K, options_.edge_band);
    if (seen.surface[k] > 0) {
      t.depth = seen.surface[k] + kCocoToBodyJoint[k].depth_below_surface;
      t.weight_depth = options_.weight_depth * std::sqrt(kCocoToBodyJoint[k].weight);
    }
  }
  if (options_.side_view_separation > 0) {
    pairSideViews(input, seen.surface, K, options_.side_view_separation, term);
  }
  return new ceres::AutoDiffCostFunction<DataTerm, kResidualsData, 3, 3, kBodyPoseSize, kShapes>(term);
}

// Stage 1 (without a previous fit): root rotation and translation on the torso keypoints; stage 2:
// everything, with the priors. Adds the iterations and costs to result; returns how stage 2 ended.
BodyFitter::SolveOutcome BodyFitter::solve(const BodyFitInput& input, const Observations& seen,
                                           const CameraIntrinsics& K, Variables* x, BodyFitResult* result,
                                           const double* hold_depth) const {
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::DENSE_QR;
  solver.logging_type = ceres::SILENT;
  solver.num_threads = 1;
  if (options_.stage1_iterations > 0 && input.previous == nullptr && !hold_depth) {
    ceres::Problem problem;
    problem.AddResidualBlock(dataTerm(input, seen, K, true), nullptr, x->root.data(), x->translation.data(),
                             x->body.data(), x->shape.data());
    problem.SetParameterBlockConstant(x->body.data());
    problem.SetParameterBlockConstant(x->shape.data());
    addUprightPrior(input, x, &problem);
    solver.max_num_iterations = options_.stage1_iterations;
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    result->iterations += static_cast<int>(summary.iterations.size()) - 1;
  }
  ceres::Problem problem;
  problem.AddResidualBlock(dataTerm(input, seen, K, false), nullptr, x->root.data(), x->translation.data(),
                           x->body.data(), x->shape.data());
  addPriors(input, x, &problem);
  if (hold_depth) {
    problem.AddResidualBlock(
        new ceres::AutoDiffCostFunction<DepthHold, 1, 3>(new DepthHold{*hold_depth, options_.weight_surface_depth}),
        nullptr, x->translation.data());
  }
  solver.max_num_iterations = options_.max_iterations;
  ceres::Solver::Summary summary;
  ceres::Solve(solver, &problem, &summary);
  result->iterations += static_cast<int>(summary.iterations.size()) - 1;
  result->initial_cost = summary.initial_cost;
  result->cost = summary.final_cost;
  return {summary.termination_type == ceres::FAILURE, summary.message};
}

// Both stages: people stand, walk and sit upright. Without it the fits leaned 16 degrees (median;
// the truth 0.6) on pf2_synth, mostly towards or away from the camera, where the keypoints hardly
// constrain the tilt, and legs outside the image followed the lean.
void BodyFitter::addUprightPrior(const BodyFitInput& input, Variables* x, ceres::Problem* problem) const {
  if (options_.weight_upright <= 0 || !input.up_c.allFinite() || input.up_c.norm() < 1e-6) return;
  problem->AddResidualBlock(new ceres::AutoDiffCostFunction<UprightPrior, 3, 3>(
                                new UprightPrior{input.up_c.normalized(), options_.weight_upright}),
                            nullptr, x->root.data());
}

// Stage 2's priors: upright, pose (and joint limits), shape, and the temporal term with a previous fit.
void BodyFitter::addPriors(const BodyFitInput& input, Variables* x, ceres::Problem* problem) const {
  addUprightPrior(input, x, problem);
  if (options_.weight_pose > 0 || options_.weight_limits > 0) {
    auto* prior = new PosePrior{relaxedBody(), {}, options_.weight_limits};
    for (int j = 1; j < kBodyJointCount; ++j) {
      // Joints no COCO keypoint observes (spine, neck, collars, feet, hands) are held closer.
      const bool unseen = j == 3 || j == 6 || j == 9 || j == 12 || j == 13 || j == 14 || j == 10 || j == 11 ||
                          j == 22 || j == 23;
      for (int k = 0; k < 3; ++k) prior->scale[3 * (j - 1) + k] = options_.weight_pose * (unseen ? 3.0 : 1.0);
    }
    problem->AddResidualBlock(
        new ceres::AutoDiffCostFunction<PosePrior, kBodyPoseSize + kLimitResiduals, kBodyPoseSize>(prior), nullptr,
        x->body.data());
  }
  if (options_.weight_shape > 0) {
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<ShapePrior, kShapes, kShapes>(
                                  new ShapePrior{options_.weight_shape}),
                              nullptr, x->shape.data());
  }
  if (input.previous != nullptr && options_.weight_temporal > 0) {
    auto* temporal = new TemporalTerm{x->body, options_.weight_temporal};
    problem->AddResidualBlock(new ceres::AutoDiffCostFunction<TemporalTerm, kBodyPoseSize, kBodyPoseSize>(temporal),
                              nullptr, x->body.data());
  }
  if (!options_.fit_shape) problem->SetParameterBlockConstant(x->shape.data());
}

std::vector<Eigen::Vector3d> depthPointsFromImage(const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                                                  int stride) {
  if (depth.type() != CV_32FC1) throw Error("depthPointsFromImage: depth must be CV_32F (metres)");
  if (stride < 1) throw Error("depthPointsFromImage: stride must be >= 1");
  std::vector<Eigen::Vector3d> points;
  for (int v = 0; v < depth.rows; v += stride) {
    const float* row = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; u += stride) {
      const float z = row[u];
      if (std::isfinite(z) && z > 0) points.push_back(intrinsics.backProject(u, v, z));
    }
  }
  return points;
}

Eigen::Isometry3d humanToWorld(const Eigen::Isometry3d& T_w_c, const Eigen::Vector3d& p_w) {
  Eigen::Isometry3d T_w_h = Eigen::Isometry3d::Identity();
  T_w_h.linear() = T_w_c.linear() * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  T_w_h.translation() = p_w;
  return T_w_h;
}

BodyParameters bodyToWorld(const BodyParameters& body_c, const Eigen::Isometry3d& T_w_c,
                           const Eigen::Vector3d& rest_pelvis) {
  // A posed point is R_0 (x - J_0) + J_0 + t; in the world R_w_c R_0 (x - J_0) + R_w_c (J_0 + t) + t_w_c.
  BodyParameters body_w = body_c;
  const double angle = body_c.pose[0].norm();
  const Eigen::Matrix3d R_0 = angle > 1e-12 ? Eigen::AngleAxisd(angle, body_c.pose[0] / angle).toRotationMatrix()
                                            : Eigen::Matrix3d::Identity();
  const Eigen::AngleAxisd root_w(T_w_c.linear() * R_0);
  body_w.pose[0] = root_w.angle() * root_w.axis();
  body_w.translation = T_w_c.linear() * (rest_pelvis + body_c.translation) + T_w_c.translation() - rest_pelvis;
  return body_w;
}

}  // namespace pf2
