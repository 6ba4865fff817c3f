#include "pf2/registration/trajectory_smoother.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace pf2 {
namespace {

// A camera moving along a gentle curve at 30 Hz, each measured position scattered by 5 mm.
Trajectory noisyPath(int frames, std::mt19937* rng, Trajectory* truth) {
  std::normal_distribution<double> noise(0.0, 0.005);
  Trajectory measured;
  for (int i = 0; i < frames; ++i) {
    const double t = i / 30.0;
    StampedPose pose;
    pose.timestamp = t;
    pose.T_w_c.translation() = Eigen::Vector3d(0.3 * t, 0.1 * std::sin(2.0 * t), 1.0 + 0.05 * t * t);
    truth->push_back(pose);
    pose.T_w_c.translation() += Eigen::Vector3d(noise(*rng), noise(*rng), noise(*rng));
    measured.push_back(pose);
  }
  return measured;
}

double rmse(const Trajectory& a, const Trajectory& b) {
  double sum = 0.0;
  for (size_t i = 0; i < a.size(); ++i) sum += (a[i].T_w_c.translation() - b[i].T_w_c.translation()).squaredNorm();
  return std::sqrt(sum / a.size());
}

TEST(TrajectorySmoother, RemovesPerFrameScatterButFollowsTheMotion) {
  std::mt19937 rng(3);
  Trajectory truth;
  const Trajectory measured = noisyPath(300, &rng, &truth);
  const Trajectory smoothed = TrajectorySmoother(TrajectorySmoother::Options()).smooth(measured);
  ASSERT_EQ(smoothed.size(), measured.size());
  const double before = rmse(measured, truth), after = rmse(smoothed, truth);
  EXPECT_GT(before, 0.0075);  // 5 mm per axis
  EXPECT_LT(after, 0.5 * before);
  for (size_t i = 0; i < smoothed.size(); ++i) {
    EXPECT_EQ(smoothed[i].timestamp, measured[i].timestamp);
    EXPECT_TRUE(smoothed[i].T_w_c.linear().isApprox(measured[i].T_w_c.linear()));  // orientation as measured
  }
}

TEST(TrajectorySmoother, KeepsAJumpWhereAPoseRestartsOrTimeSkips) {
  Trajectory measured;
  for (int i = 0; i < 20; ++i) {
    StampedPose pose;
    pose.timestamp = i / 30.0 + (i >= 15 ? 1.0 : 0.0);  // a second without frames before frame 15
    pose.T_w_c.translation() = Eigen::Vector3d(i < 10 ? 0.0 : (i < 15 ? 0.5 : 1.0), 0.0, 0.0);
    measured.push_back(pose);
  }
  std::vector<bool> restarts(measured.size(), false);
  restarts[10] = true;  // relocalised: 0.5 m away from the frame before
  const Trajectory smoothed = TrajectorySmoother(TrajectorySmoother::Options()).smooth(measured, restarts);
  // Each segment is constant: smoothing changes nothing, the jumps stay whole.
  EXPECT_LT(rmse(smoothed, measured), 1e-9);
  // Without the restart flag, the jump at frame 10 is smeared over its neighbours.
  const Trajectory smeared = TrajectorySmoother(TrajectorySmoother::Options()).smooth(measured);
  EXPECT_GT((smeared[9].T_w_c.translation() - measured[9].T_w_c.translation()).norm(), 0.01);
}

TEST(TrajectorySmoother, NoiseZeroLeavesTheTrajectoryAsMeasured) {
  std::mt19937 rng(5);
  Trajectory truth;
  const Trajectory measured = noisyPath(50, &rng, &truth);
  TrajectorySmoother::Options off;
  off.position_noise = 0.0;
  EXPECT_EQ(rmse(TrajectorySmoother(off).smooth(measured), measured), 0.0);
}

}  // namespace
}  // namespace pf2
