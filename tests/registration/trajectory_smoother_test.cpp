#include "pf2/registration/trajectory_smoother.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

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

// A camera swinging along x, x(t) = 0.2 sin(2 t) m (RMS acceleration 0.2 * 2^2 / sqrt(2) = 0.57
// m/s^2), or standing still (amplitude 0), for `seconds` at 30 Hz with 5 mm of scatter.
Trajectory swingingCamera(double amplitude, double seconds, std::mt19937* rng, Trajectory* truth) {
  std::normal_distribution<double> noise(0.0, 0.005);
  Trajectory measured;
  for (int i = 0; i < static_cast<int>(seconds * 30.0); ++i) {
    StampedPose pose;
    pose.timestamp = i / 30.0;
    pose.T_w_c.translation() = Eigen::Vector3d(amplitude * std::sin(2.0 * pose.timestamp), 0.0, 1.0);
    truth->push_back(pose);
    pose.T_w_c.translation() += Eigen::Vector3d(noise(*rng), noise(*rng), noise(*rng));
    measured.push_back(pose);
  }
  return measured;
}

TEST(TrajectorySmoother, MeasuresTheCamerasAccelerationFromTheRun) {
  std::mt19937 rng(7);
  Trajectory truth;
  TrajectorySmoother::Options unscaled;
  unscaled.acceleration_scale = 1.0;
  unscaled.acceleration_floor = 0.001;
  // Second differences over 0.5 s see 0.92 of the swing's 0.57 m/s^2 (sin(0.5) / 0.5 squared).
  const Trajectory swinging = swingingCamera(0.2, 10.0, &rng, &truth);
  EXPECT_NEAR(TrajectorySmoother(unscaled).accelerationNoise(swinging), 0.52, 0.04);
  EXPECT_NEAR(TrajectorySmoother(TrajectorySmoother::Options()).accelerationNoise(swinging), 1.5 * 0.52, 0.06);
  // A still camera: the scatter alone, sqrt(6) * 5 mm / (0.5 s)^2 = 0.05 m/s^2 per axis; below
  // the floor, the floor.
  truth.clear();
  const Trajectory still = swingingCamera(0.0, 10.0, &rng, &truth);
  EXPECT_LT(TrajectorySmoother(unscaled).accelerationNoise(still), 0.1);
  TrajectorySmoother::Options floored;
  floored.acceleration_floor = 0.3;
  EXPECT_EQ(TrajectorySmoother(floored).accelerationNoise(still), 0.3);
  const TrajectorySmoother::Options defaults;
  // Not measured, or too short a run (1 s, under three baselines): the configured value.
  TrajectorySmoother::Options fixed;
  fixed.measure_acceleration = false;
  EXPECT_EQ(TrajectorySmoother(fixed).accelerationNoise(swinging), fixed.acceleration_noise);
  truth.clear();
  const Trajectory short_run = swingingCamera(0.2, 1.0, &rng, &truth);
  EXPECT_EQ(TrajectorySmoother(defaults).accelerationNoise(short_run), defaults.acceleration_noise);
}

TEST(TrajectorySmoother, RefusesABaselineThatIsNotPositive) {
  TrajectorySmoother::Options zero;
  zero.acceleration_baseline = 0.0;  // would never step through the run
  EXPECT_THROW(TrajectorySmoother{zero}, Error);
  zero.measure_acceleration = false;  // not measured: the baseline is not read
  EXPECT_NO_THROW(TrajectorySmoother{zero});
}

TEST(TrajectorySmoother, AStillCameraIsSmoothedCloserToTheTruthWithItsMeasuredAcceleration) {
  std::mt19937 rng(11);
  Trajectory truth;
  const Trajectory measured = swingingCamera(0.0, 10.0, &rng, &truth);
  TrajectorySmoother::Options fixed;
  fixed.measure_acceleration = false;  // 0.5 m/s^2, five times the floor the still camera measures
  const double with_fixed = rmse(TrajectorySmoother(fixed).smooth(measured), truth);
  const double with_measured = rmse(TrajectorySmoother(TrajectorySmoother::Options()).smooth(measured), truth);
  EXPECT_LT(with_measured, 0.75 * with_fixed);
  // And a swinging one is still followed: the measured noise does not flatten its motion.
  truth.clear();
  const Trajectory swinging = swingingCamera(0.2, 10.0, &rng, &truth);
  EXPECT_LT(rmse(TrajectorySmoother(TrajectorySmoother::Options()).smooth(swinging), truth), 0.6 * rmse(swinging, truth));
}

}  // namespace
}  // namespace pf2
