#include "pf2/io/trajectory_io.h"

#include <sys/stat.h>

#include <fstream>

#include <Eigen/SVD>
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


// The dataset's axis swap, written out here independently of the code under test.
Eigen::Isometry3d axisSwap() {
  Eigen::Isometry3d T_ros = Eigen::Isometry3d::Identity();
  T_ros.linear() << -1, 0, 0, 0, 0, 1, 0, 1, 0;
  return T_ros;
}

// Largest difference of position (m) and quaternion (sign-aligned) between two poses.
void expectSamePose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double tolerance) {
  EXPECT_LT((a.translation() - b.translation()).cwiseAbs().maxCoeff(), tolerance);
  const Eigen::Quaterniond qa(a.rotation());
  Eigen::Quaterniond qb(b.rotation());
  if (qa.dot(qb) < 0) qb.coeffs() *= -1.0;
  EXPECT_LT((qa.coeffs() - qb.coeffs()).cwiseAbs().maxCoeff(), tolerance);
}

// Two poses of one stamp (e.g. every stamp equal) are a broken file, not a trajectory to score.
TEST(TrajectoryIo, OnePosePerTimestamp) {
  const std::string path = testing::TempDir() + "pf2_same_stamps.txt";
  std::ofstream(path) << "# t x y z qx qy qz qw\n1.0 0 0 0 0 0 0 1\n2.0 1 0 0 0 0 0 1\n1.0 2 0 0 0 0 0 1\n";
  try {
    readTrajectory(path);
    FAIL() << "a repeated timestamp was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":4: timestamp already given on line 2"), std::string::npos)
        << e.what();
  }
}

TEST(TrajectoryIo, FormatNames) {
  EXPECT_EQ(parseTrajectoryFormat("tum", "--gt-format"), TrajectoryFormat::kTum);
  EXPECT_EQ(parseTrajectoryFormat("bonn", "--gt-format"), TrajectoryFormat::kBonn);
  try {
    parseTrajectoryFormat("Bonn", "--gt-format");
    FAIL() << "unknown format accepted";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "--gt-format: unknown trajectory format 'Bonn' (allowed: tum, bonn)");
  }
}

TEST(TrajectoryIo, BonnMarkerToCameraIsThePublishedTransformOrthonormalised) {
  const Eigen::Isometry3d T_m = bonnMarkerToCamera();
  const Eigen::Matrix3d R = T_m.rotation();
  EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_NEAR(R.determinant(), 1.0, 1e-12);
  // The nearest rotation to the dataset's four-digit matrix (polar factor U V^T of its SVD).
  Eigen::Matrix3d published;
  published << 1.0157, 0.1828, -0.2389, 0.0009, -0.8431, -0.6413, -0.3009, 0.6147, -0.8085;
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(published, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix3d nearest = svd.matrixU() * svd.matrixV().transpose();
  EXPECT_LT((R - nearest).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_LT((T_m.translation() - Eigen::Vector3d(0.0113, -0.0098, 0.0111)).norm(), 1e-12);
}

TEST(TrajectoryIo, BonnMarkerFileFromKnownCameraPosesReadsBackAsThem) {
  // Camera poses T_w_c -> marker poses by the inverse rule T_gt = T_ros T_w_c T_m^-1 T_ros,
  // written as a Bonn groundtruth.txt, read back with the bonn format.
  const Eigen::Isometry3d T_ros = axisSwap();
  const Eigen::Isometry3d T_m = bonnMarkerToCamera();
  Trajectory cameras, markers;
  for (int i = 0; i < 20; ++i) {
    StampedPose camera;
    camera.timestamp = 1548339828.0 + 0.033 * i;
    camera.T_w_c.linear() = (Eigen::AngleAxisd(0.3 * i, Eigen::Vector3d(1, 2, 3).normalized()) *
                             Eigen::AngleAxisd(2.5, Eigen::Vector3d::UnitX()))
                                .toRotationMatrix();
    camera.T_w_c.translation() = Eigen::Vector3d(0.4 - 0.05 * i, 1.5, -1.6 + 0.02 * i);
    StampedPose marker = camera;
    marker.T_w_c = T_ros * camera.T_w_c * T_m.inverse() * T_ros;
    cameras.push_back(camera);
    markers.push_back(marker);
  }
  const std::string path = testing::TempDir() + "pf2_bonn_marker.txt";
  writeTrajectory(path, markers);
  const Trajectory read = readTrajectory(path, TrajectoryFormat::kBonn);
  ASSERT_EQ(read.size(), cameras.size());
  for (size_t i = 0; i < read.size(); ++i) {
    EXPECT_NEAR(read[i].timestamp, cameras[i].timestamp, 1e-6);
    expectSamePose(read[i].T_w_c, cameras[i].T_w_c, 1e-7);
  }
  // The tum format leaves the marker poses as they are: the conversion is not a no-op.
  EXPECT_GT((readTrajectory(path, TrajectoryFormat::kTum)[0].T_w_c.translation() -
             cameras[0].T_w_c.translation()).norm(), 0.5);
}

TEST(TrajectoryIo, BonnCrowdMarkerPosesGiveThePublishedCameraPosesWhenPresent) {
  const std::string dir = std::string(PF2_SHARED_DATA) + "/bonn_crowd_250_150";
  struct stat info;
  if (::stat(dir.c_str(), &info) != 0) GTEST_SKIP() << "no real data at " << dir;
  const Trajectory converted =
      readTrajectory(dir + "/gt/groundtruth_marker.txt", TrajectoryFormat::kBonn);
  const Trajectory expected = readTrajectory(dir + "/groundtruth.txt");
  ASSERT_EQ(converted.size(), expected.size());
  ASSERT_GT(converted.size(), 100u);
  for (size_t i = 0; i < converted.size(); ++i) {
    EXPECT_NEAR(converted[i].timestamp, expected[i].timestamp, 1e-5);
    expectSamePose(converted[i].T_w_c, expected[i].T_w_c, 1e-5);
  }
}

}  // namespace
}  // namespace pf2
