#pragma once
// The known body of the body tests: the shipped model, a walking-like posture at 3 m, and the
// exact keypoints the fitter expects of it.
#include <cstdlib>
#include <random>

#include <Eigen/Geometry>

#include "pf2/body/body_fitter.h"
#include "pf2/body/body_model.h"

namespace pf2 {

inline const BodyModel& defaultModel() {
  static const BodyModel model = [] {
    ::unsetenv("PF2_BODY_MODEL");
    return BodyModel::loadDefault();
  }();
  return model;
}

// A walking-like posture seen from 3 m, turned 25° from facing the camera, in an upright camera.
inline BodyParameters knownBody() {
  BodyParameters b;
  b.shape.setZero();
  b.shape[0] = 0.8;   // taller
  b.shape[3] = -0.5;  // lighter
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.44, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                            Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::AngleAxisd root(R);
  b.pose[0] = root.angle() * root.axis();
  b.pose[1] = {-0.35, 0, 0.05};  // left hip forward
  b.pose[2] = {0.25, 0, -0.05};  // right hip back
  b.pose[4] = {0.5, 0, 0};       // left knee bent
  b.pose[5] = {0.15, 0, 0};
  b.pose[16] = {0.2, 0.1, -1.3};  // arms down, swinging
  b.pose[17] = {-0.2, -0.1, 1.25};
  b.pose[18] = {0, -0.5, 0};  // left elbow bent
  b.pose[19] = {0, 0.2, 0};
  b.translation = {0.15, 0.1, 3.0};
  return b;
}

// Exact keypoints of a body: where the fitter expects them (BodyFitter::keypointPoints), projected.
inline BodyFitInput keypointsOf(const BodyParameters& body, const CameraIntrinsics& K, double noise_px = 0.0,
                                unsigned seed = 1) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_px > 0 ? noise_px : 1.0);
  const auto points = BodyFitter(defaultModel()).keypointPoints(body);
  BodyFitInput input;
  for (int k = 0; k < kCocoKeypointCount; ++k) {
    if (kCocoToBodyJoint[k].joint < 0) continue;
    const Eigen::Vector2d px = K.project(points[k]);
    input.keypoints[k] = {px.x() + (noise_px > 0 ? noise(rng) : 0.0), px.y() + (noise_px > 0 ? noise(rng) : 0.0), 1.0};
  }
  return input;
}

}  // namespace pf2
