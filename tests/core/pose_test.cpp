#include "pf2/core/pose.h"

#include <cmath>

#include <gtest/gtest.h>

namespace pf2 {
namespace {

Eigen::Isometry3d makePose(const Eigen::Vector3d& axis, double angle, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  T.translation() = t;
  return T;
}

TEST(Pose, TumLineRoundTrip) {
  StampedPose pose{1305031453.359684, makePose({0.2, -1, 0.3}, 1.1, {1.5, -0.25, 3.125})};
  StampedPose parsed;
  ASSERT_TRUE(parseTumLine(toTumLine(pose), &parsed));
  EXPECT_NEAR(parsed.timestamp, pose.timestamp, 1e-6);
  EXPECT_LT((parsed.T_w_c.matrix() - pose.T_w_c.matrix()).cwiseAbs().maxCoeff(), 1e-8);
}

TEST(Pose, ParseRejectsBadLines) {
  StampedPose pose;
  EXPECT_FALSE(parseTumLine("1.0 2 3 4 0 0 0", &pose));         // seven numbers
  EXPECT_FALSE(parseTumLine("1.0 2 3 4 0 0 0 0", &pose));       // zero quaternion
  EXPECT_FALSE(parseTumLine("1.0 2 nan 4 0 0 0 1", &pose));     // not finite
  EXPECT_FALSE(parseTumLine("1.0 2 3 x 0 0 0 1", &pose));       // not a number
  EXPECT_TRUE(parseTumLine("1.0 2 3 4 0 0 0 2 extra", &pose));  // extra columns, scaled quaternion
  EXPECT_NEAR(pose.T_w_c.linear().determinant(), 1.0, 1e-12);
}

TEST(Pose, InterpolateHalfwayIsSlerpAndLerp) {
  const Eigen::Isometry3d a = makePose({0, 0, 1}, 0.0, {0, 0, 0});
  const Eigen::Isometry3d b = makePose({0, 0, 1}, 1.0, {2, -4, 6});
  const Eigen::Isometry3d mid = interpolate(a, b, 0.5);
  EXPECT_NEAR(rotationAngle(mid.rotation()), 0.5, 1e-12);
  EXPECT_NEAR((mid.translation() - Eigen::Vector3d(1, -2, 3)).norm(), 0.0, 1e-12);
  const Eigen::Isometry3d quarter = interpolate(a, b, 0.25);
  EXPECT_NEAR(rotationAngle(quarter.rotation()), 0.25, 1e-12);
}

TEST(Pose, InterpolateAtRespectsSpanAndGaps) {
  Trajectory trajectory = {{0.0, makePose({1, 0, 0}, 0.0, {0, 0, 0})},
                           {1.0, makePose({1, 0, 0}, 0.4, {1, 0, 0})},
                           {5.0, makePose({1, 0, 0}, 0.8, {2, 0, 0})}};
  Eigen::Isometry3d T;
  ASSERT_TRUE(interpolateAt(trajectory, 0.75, 1.5, &T));
  EXPECT_NEAR(T.translation().x(), 0.75, 1e-12);
  EXPECT_NEAR(rotationAngle(T.rotation()), 0.3, 1e-12);
  ASSERT_TRUE(interpolateAt(trajectory, 1.0, 1.5, &T));  // exact stamp
  EXPECT_NEAR(T.translation().x(), 1.0, 1e-12);
  EXPECT_FALSE(interpolateAt(trajectory, -0.1, 1.5, &T));  // before the start
  EXPECT_FALSE(interpolateAt(trajectory, 5.1, 1.5, &T));   // after the end
  EXPECT_FALSE(interpolateAt(trajectory, 3.0, 1.5, &T));   // 4 s gap is not bridged
  EXPECT_TRUE(interpolateAt(trajectory, 3.0, 4.5, &T));
}

TEST(Pose, RotationAngleNearZeroAndPi) {
  for (double angle : {1e-9, 1e-4, 0.5, 3.0, M_PI - 1e-7}) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(angle, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    EXPECT_NEAR(rotationAngle(R), angle, 1e-8) << angle;
  }
}

}  // namespace
}  // namespace pf2
