// UpDirectionEstimator on exact depth of the box room (world y down, floor at y = 1.2 m): a
// camera pitched and rolled, a view with no horizontal surface, the estimate settling, bad input.
#include <cmath>

#include <gtest/gtest.h>

#include "analytic_scene.h"
#include "pf2/core/error.h"
#include "pf2/surface/up_direction.h"

namespace pf2 {
namespace {

const Eigen::Vector3d kUpRoom(0, -1, 0);

double degreesBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
}

// A camera 1.2 m above the floor looking 20 degrees down, rolled 8 degrees about its axis.
Eigen::Isometry3d pitchedRolledCamera() {
  const Eigen::Vector3d position(0.3, 0.0, -1.2);
  const Eigen::Vector3d forward = Eigen::Vector3d(0, std::sin(20 * M_PI / 180), std::cos(20 * M_PI / 180));
  const Eigen::Vector3d rolled_up = Eigen::AngleAxisd(8 * M_PI / 180, forward) * kUpRoom;
  return test::lookAt(position, position + forward, rolled_up);
}

// The world of pf2_slam is the first camera's frame: up there is what is checked, against the
// camera's -y (the fallback), which is 21 degrees off.
TEST(UpDirectionEstimator, FindsUpForAPitchedAndRolledCamera) {
  const CameraIntrinsics K;
  const Eigen::Isometry3d T_room_c = pitchedRolledCamera();
  cv::Mat depth;
  test::boxRoom().render(K, T_room_c, &depth);
  const Eigen::Vector3d truth_c = T_room_c.linear().transpose() * kUpRoom;
  UpDirectionEstimator up;
  EXPECT_FALSE(up.estimated());
  EXPECT_GT(degreesBetween(up.up_w(), truth_c), 15.0);  // the fallback
  ASSERT_TRUE(up.update(depth, K, Eigen::Isometry3d::Identity()));
  EXPECT_TRUE(up.estimated());
  EXPECT_LT(degreesBetween(up.up_w(), truth_c), 0.5);
  // The same frame seen from the room frame gives the room's up.
  UpDirectionEstimator in_room;
  ASSERT_TRUE(in_room.update(depth, K, T_room_c));
  EXPECT_LT(degreesBetween(in_room.up_w(), kUpRoom), 0.5);
}

TEST(UpDirectionEstimator, AViewWithoutFloorSaysNothing) {
  const CameraIntrinsics K;
  // 0.6 m from the wall, level: neither floor nor ceiling in the view.
  const Eigen::Isometry3d T_room_c = test::lookAt({0, 0, 1.4}, {0, 0, 3});
  cv::Mat depth;
  test::boxRoom().render(K, T_room_c, &depth);
  const Eigen::Vector3d fallback(0.1, -1, 0);
  UpDirectionEstimator up(UpDirectionEstimator::Options(), fallback);
  EXPECT_FALSE(up.update(depth, K, T_room_c));
  EXPECT_FALSE(up.estimated());
  EXPECT_LT(degreesBetween(up.up_w(), fallback), 1e-9);
}

TEST(UpDirectionEstimator, SettlesAndThenKeepsItsEstimate) {
  const CameraIntrinsics K;
  const Eigen::Isometry3d T_room_c = pitchedRolledCamera();
  cv::Mat depth;
  test::boxRoom().render(K, T_room_c, &depth);
  UpDirectionEstimator::Options options;
  options.settled_normals = 1;
  UpDirectionEstimator up(options);
  ASSERT_TRUE(up.update(depth, K, T_room_c));
  EXPECT_TRUE(up.settled());
  // A frame with a wrong pose no longer moves it.
  const Eigen::Isometry3d wrong(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()));
  EXPECT_FALSE(up.update(depth, K, wrong * T_room_c));
  EXPECT_LT(degreesBetween(up.up_w(), kUpRoom), 0.5);
}

TEST(UpDirectionEstimator, RejectsBadInput) {
  UpDirectionEstimator::Options bad;
  bad.stride_px = 0;
  EXPECT_THROW(UpDirectionEstimator{bad}, Error);
  bad = UpDirectionEstimator::Options();
  bad.fine_angle = 2 * bad.max_angle;
  EXPECT_THROW(UpDirectionEstimator{bad}, Error);
  EXPECT_THROW(UpDirectionEstimator(UpDirectionEstimator::Options(), Eigen::Vector3d::Zero()), Error);
  UpDirectionEstimator up;
  const cv::Mat integer_depth(480, 640, CV_16U, cv::Scalar(1000));
  EXPECT_THROW(up.update(integer_depth, CameraIntrinsics(), Eigen::Isometry3d::Identity()), Error);
  EXPECT_FALSE(up.update(cv::Mat(), CameraIntrinsics(), Eigen::Isometry3d::Identity()));
}

}  // namespace
}  // namespace pf2
