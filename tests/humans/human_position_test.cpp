#include "pf2/humans/human_position.h"

#include <cmath>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

TEST(HumanPosition, MeanDepthIgnoresMissingAndInvalidPixels) {
  cv::Mat depth(2, 3, CV_32F, cv::Scalar(0));
  depth.at<float>(0, 0) = 2.0f;
  depth.at<float>(0, 2) = 3.0f;
  depth.at<float>(1, 1) = 4.0f;
  depth.at<float>(1, 2) = std::nanf("");
  depth.at<float>(1, 0) = -1.0f;
  EXPECT_DOUBLE_EQ(meanDepth(depth), 3.0);
  EXPECT_DOUBLE_EQ(meanDepth(cv::Mat(4, 4, CV_32F, cv::Scalar(0))), 0.0);
  EXPECT_DOUBLE_EQ(meanDepth(cv::Mat()), 0.0);
  EXPECT_THROW(meanDepth(cv::Mat(2, 2, CV_16U, cv::Scalar(1))), Error);
}

TEST(HumanPosition, EquationTwoAndThree) {
  const CameraIntrinsics K = CameraIntrinsics::tumFreiburg3();
  // Box centre (300, 200), d_m = 2: x = (600 - 640.2) / (2 * 535.4) * 2, y = (400 - 495.2) / (2 * 539.2) * 2.
  const Eigen::Vector3d p_c = humanCentreInCamera(250, 100, 350, 300, 2.0, K);
  EXPECT_NEAR(p_c.x(), -40.2 / 535.4, 1e-12);
  EXPECT_NEAR(p_c.y(), -95.2 / 539.2, 1e-12);
  EXPECT_DOUBLE_EQ(p_c.z(), 2.0);
  // The centre projects back to the box centre.
  EXPECT_TRUE(K.project(p_c).isApprox(Eigen::Vector2d(300, 200), 1e-12));
  // Eq. 3: camera 1 m along world x, turned 90 degrees about y (camera z -> world -x).
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  T_w_c.linear() = Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T_w_c.translation() = Eigen::Vector3d(1, 0, 0);
  const Eigen::Vector3d p_w = humanCentreInWorld(T_w_c, Eigen::Vector3d(0, 0, 2));
  EXPECT_TRUE(p_w.isApprox(Eigen::Vector3d(-1, 0, 0), 1e-12)) << p_w.transpose();
}

}  // namespace
}  // namespace pf2
