#include "pf2/surface/occupancy_map.h"

#include <gtest/gtest.h>

#include "analytic_scene.h"
#include "pf2/core/error.h"

namespace pf2 {
namespace {

using test::AnalyticScene;
using test::boxRoom;
using test::lookAt;

// Cameras at the back of the room looking at the far wall, the person halfway between.
Eigen::Isometry3d pose(int i) {
  return lookAt(Eigen::Vector3d(0.05 * (i % 5) - 0.1, -0.3, -1.5), Eigen::Vector3d(0.0, 0.0, 2.0));
}

int occupiedInside(const OccupancyMap& map, const test::Box& box) {
  int count = 0;
  for (const Eigen::Vector3d& c : map.occupiedCentres()) {
    count += (c.array() > box.min.array()).all() && (c.array() < box.max.array()).all();
  }
  return count;
}

TEST(OccupancyMap, PersonWhoWalksAwayLeavesNoOccupiedCells) {
  const AnalyticScene empty = boxRoom();
  AnalyticScene with_person = empty;
  const test::Box person{Eigen::Vector3d(-0.25, -0.6, 0.2), Eigen::Vector3d(0.25, 1.2, 0.5)};
  with_person.boxes.push_back(person);
  const CameraIntrinsics K;
  OccupancyMap map;
  cv::Mat depth, bgr;
  for (int i = 0; i < 3; ++i) {
    with_person.render(K, pose(i), &depth, &bgr);
    map.insert(depth, bgr, K, pose(i));
  }
  // The person is in the map while present.
  const int while_present = occupiedInside(map, person);
  EXPECT_GT(while_present, 20);
  EXPECT_TRUE(map.isOccupied(Eigen::Vector3d(0.0, 0.0, 0.22)));
  for (int i = 3; i < 15; ++i) {
    empty.render(K, pose(i), &depth, &bgr);
    map.insert(depth, bgr, K, pose(i));
  }
  EXPECT_EQ(occupiedInside(map, person), 0);
  EXPECT_FALSE(map.isOccupied(Eigen::Vector3d(0.0, 0.0, 0.22)));
  // The far wall (z = 2) behind the person is occupied.
  EXPECT_TRUE(map.isOccupied(Eigen::Vector3d(0.0, 0.0, 2.01)));
  // Every occupied cell lies at a wall.
  for (const Eigen::Vector3d& c : map.occupiedCentres()) {
    EXPECT_LT(empty.distance(c), 0.05 * std::sqrt(3.0)) << c.transpose();
  }
}

TEST(OccupancyMap, RejectsBadImages) {
  OccupancyMap map;
  const CameraIntrinsics K;
  EXPECT_THROW(map.insert(cv::Mat(10, 10, CV_32F), cv::Mat(), K, Eigen::Isometry3d::Identity()), Error);
  OccupancyMap::Options bad;
  bad.resolution = -1;
  EXPECT_THROW(OccupancyMap{bad}, Error);
}

}  // namespace
}  // namespace pf2
