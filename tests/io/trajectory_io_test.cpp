#include "pf2/io/trajectory_io.h"

#include <fstream>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

TEST(TrajectoryIo, WriteReadRoundTripSorted) {
  Trajectory trajectory;
  for (int i = 4; i >= 0; --i) {  // written out of order, read back sorted
    StampedPose pose;
    pose.timestamp = 100.0 + 0.033 * i;
    pose.T_w_c.linear() = Eigen::AngleAxisd(0.1 * i, Eigen::Vector3d::UnitY()).toRotationMatrix();
    pose.T_w_c.translation() = Eigen::Vector3d(0.01 * i, -0.5, 2.0);
    trajectory.push_back(pose);
  }
  const std::string path = testing::TempDir() + "pf2_traj.txt";
  writeTrajectory(path, trajectory);
  const Trajectory loaded = readTrajectory(path);
  ASSERT_EQ(loaded.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_NEAR(loaded[i].timestamp, 100.0 + 0.033 * i, 1e-6);
    EXPECT_NEAR(loaded[i].T_w_c.translation().x(), 0.01 * i, 1e-9);
  }
}

TEST(TrajectoryIo, GroundTruthStyleHeaderAndMalformedLine) {
  const std::string path = testing::TempDir() + "pf2_gt.txt";
  std::ofstream(path) << "# ground truth trajectory\r\n# timestamp tx ty tz qx qy qz qw\r\n"
                         "1305031452.8694 1.2325 0.9180 1.5338 0.8630 0.3310 -0.1994 -0.3255\r\n"
                         "1305031452.8795 1.2335 0.9177 1.5327 0.8639 0.3285 -0.1993\r\n";
  try {
    readTrajectory(path);
    FAIL() << "seven columns accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":4:"), std::string::npos) << e.what();
  }
  EXPECT_THROW(readTrajectory(testing::TempDir() + "pf2_no_such_traj.txt"), Error);
}

}  // namespace
}  // namespace pf2
