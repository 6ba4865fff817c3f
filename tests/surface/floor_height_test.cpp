// FloorEstimator on exact depth of the box room (world y down, floor at y = 1.2 m, so up = -y and
// the floor's height along up is -1.2 m): with a table top in view, without any floor, settling,
// bad input.
#include <gtest/gtest.h>

#include "analytic_scene.h"
#include "pf2/core/error.h"
#include "pf2/surface/floor_height.h"

namespace pf2 {
namespace {

const Eigen::Vector3d kUpRoom(0, -1, 0);

// A camera 1.2 m above the floor (at y = 0) looking 25 degrees down at the far wall.
Eigen::Isometry3d pitchedCamera() {
  const Eigen::Vector3d position(0.3, 0.0, -1.2);
  return test::lookAt(position, position + Eigen::Vector3d(0, std::sin(25 * M_PI / 180), std::cos(25 * M_PI / 180)));
}

TEST(FloorEstimator, TheLowestPileOfHeightsIsTheFloorNotTheTable) {
  const CameraIntrinsics K;
  test::AnalyticScene scene = test::boxRoom();
  scene.boxes.push_back({Eigen::Vector3d(-0.8, 0.45, 0.4), Eigen::Vector3d(1.2, 1.2, 1.4)});  // table top 0.75 m high
  cv::Mat depth;
  scene.render(K, pitchedCamera(), &depth);
  FloorEstimator floor;
  EXPECT_FALSE(floor.found());
  for (int frame = 0; frame < 3; ++frame) floor.update(depth, K, pitchedCamera(), kUpRoom);
  ASSERT_TRUE(floor.found());
  EXPECT_NEAR(floor.height(), -1.2, 0.015);
  // The same frame in the camera's own world (pf2_slam's): the floor 1.2 m below the camera.
  FloorEstimator in_camera;
  const Eigen::Vector3d up_c = pitchedCamera().linear().transpose() * kUpRoom;
  for (int frame = 0; frame < 3; ++frame) in_camera.update(depth, K, Eigen::Isometry3d::Identity(), up_c);
  ASSERT_TRUE(in_camera.found());
  EXPECT_NEAR(in_camera.height(), -1.2, 0.015);
}

TEST(FloorEstimator, AViewWithoutFloorFindsNone) {
  const CameraIntrinsics K;
  cv::Mat depth;
  const Eigen::Isometry3d T_room_c = test::lookAt({0, 0, 1.4}, {0, 0, 3});  // level, 0.6 m from the wall
  test::boxRoom().render(K, T_room_c, &depth);
  FloorEstimator floor;
  for (int frame = 0; frame < 3; ++frame) floor.update(depth, K, T_room_c, kUpRoom);
  EXPECT_FALSE(floor.found());
}

TEST(FloorEstimator, SettlesAndThenKeepsItsEstimate) {
  const CameraIntrinsics K;
  cv::Mat depth;
  test::boxRoom().render(K, pitchedCamera(), &depth);
  FloorEstimator::Options options;
  options.settled_points = options.min_points;
  FloorEstimator floor(options);
  floor.update(depth, K, pitchedCamera(), kUpRoom);
  ASSERT_TRUE(floor.found());
  const double settled = floor.height();
  Eigen::Isometry3d raised = pitchedCamera();
  raised.translation().y() -= 0.5;  // a wrong pose no longer moves it
  floor.update(depth, K, raised, kUpRoom);
  EXPECT_EQ(floor.height(), settled);
}

TEST(FloorEstimator, RejectsBadInput) {
  FloorEstimator::Options bad;
  bad.bin_size = 0;
  EXPECT_THROW(FloorEstimator{bad}, Error);
  bad = FloorEstimator::Options();
  bad.settled_points = bad.min_points - 1;
  EXPECT_THROW(FloorEstimator{bad}, Error);
  FloorEstimator floor;
  EXPECT_THROW(floor.update(cv::Mat(4, 4, CV_16U, cv::Scalar(1000)), CameraIntrinsics(), Eigen::Isometry3d::Identity(),
                            kUpRoom),
               Error);
}

}  // namespace
}  // namespace pf2
