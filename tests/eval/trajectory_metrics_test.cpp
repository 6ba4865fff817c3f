#include "pf2/eval/trajectory_metrics.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

// A hand-held-like trajectory: a wobbly loop with changing orientation, 30 Hz.
Trajectory makeTrajectory(int n, double t0 = 1000.0) {
  Trajectory trajectory;
  for (int i = 0; i < n; ++i) {
    const double s = i / 30.0;
    StampedPose pose;
    pose.timestamp = t0 + s;
    pose.T_w_c.translation() =
        Eigen::Vector3d(1.5 * std::cos(0.3 * s), 0.2 * std::sin(1.7 * s), 1.0 * std::sin(0.3 * s));
    pose.T_w_c.linear() = (Eigen::AngleAxisd(0.3 * s, Eigen::Vector3d::UnitY()) *
                           Eigen::AngleAxisd(0.1 * std::sin(s), Eigen::Vector3d::UnitX()))
                              .toRotationMatrix();
    trajectory.push_back(pose);
  }
  return trajectory;
}

Trajectory transformed(const Trajectory& trajectory, const Eigen::Isometry3d& T, double scale = 1.0) {
  Trajectory result = trajectory;
  for (StampedPose& pose : result) {
    pose.T_w_c.translation() = scale * (T * pose.T_w_c.translation());
    pose.T_w_c.linear() = T.linear() * pose.T_w_c.linear();
  }
  return result;
}

Eigen::Isometry3d someMisalignment() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(2.1, Eigen::Vector3d(0.3, -0.8, 0.5).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(4.0, -2.5, 0.7);
  return T;
}

TEST(Ate, TrajectoryAgainstItselfIsZero) {
  const Trajectory gt = makeTrajectory(300);
  const AteResult ate = computeAte(gt, gt);
  EXPECT_EQ(ate.translation.count, 300);
  EXPECT_LT(ate.translation.rmse, 1e-12);
  EXPECT_LT(ate.translation.max, 1e-12);
}

TEST(Ate, RecoversRigidMisalignmentExactly) {
  const Trajectory gt = makeTrajectory(300);
  const Eigen::Isometry3d T = someMisalignment();
  const AteResult ate = computeAte(gt, transformed(gt, T));
  EXPECT_LT(ate.translation.max, 1e-9);
  // The alignment found is the inverse of the misalignment applied.
  EXPECT_LT((ate.rotation - T.linear().transpose()).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(ate.scale, 1.0, 0.0);
}

TEST(Ate, ScaleOnlyWhenAsked) {
  const Trajectory gt = makeTrajectory(300);
  const Trajectory est = transformed(gt, someMisalignment(), 0.5);
  EXPECT_GT(computeAte(gt, est).translation.rmse, 0.1);  // rigid alignment cannot undo the scale
  AteOptions options;
  options.estimate_scale = true;
  const AteResult ate = computeAte(gt, est, options);
  EXPECT_LT(ate.translation.max, 1e-9);
  EXPECT_NEAR(ate.scale, 2.0, 1e-9);
}

TEST(Ate, AddedNoiseGivesItsAnalyticRmse) {
  // Every position is displaced by exactly 2 cm along a direction that alternates sign, so the
  // displacements have zero mean and no rotation can absorb them: the RMSE is 0.02 m.
  const Trajectory gt = makeTrajectory(400);
  Trajectory est = gt;
  std::mt19937 random(7);
  std::normal_distribution<double> gauss;
  for (size_t i = 0; i < est.size(); i += 2) {
    const Eigen::Vector3d direction = Eigen::Vector3d(gauss(random), gauss(random), gauss(random)).normalized();
    est[i].T_w_c.translation() += 0.02 * direction;
    est[i + 1].T_w_c.translation() -= 0.02 * direction;
  }
  const AteResult ate = computeAte(gt, est);
  EXPECT_NEAR(ate.translation.rmse, 0.02, 2e-4);
  EXPECT_NEAR(ate.translation.mean, 0.02, 3e-4);
  EXPECT_LT(ate.translation.std, 1e-3);
}

TEST(Ate, GaussianNoiseRmseMatchesSigma) {
  // Isotropic Gaussian noise of sigma per axis: E[|e|^2] = 3 sigma^2, less the 6 degrees of freedom
  // the alignment removes (negligible for 3000 poses).
  const Trajectory gt = makeTrajectory(3000);
  Trajectory est = gt;
  std::mt19937 random(11);
  const double sigma = 0.01;
  std::normal_distribution<double> gauss(0.0, sigma);
  for (StampedPose& pose : est) {
    pose.T_w_c.translation() += Eigen::Vector3d(gauss(random), gauss(random), gauss(random));
  }
  const double expected = std::sqrt(3.0) * sigma;
  EXPECT_NEAR(computeAte(gt, est).translation.rmse, expected, 0.04 * expected);
}

TEST(Ate, AssociatesByTimestampWithinWindow) {
  const Trajectory gt = makeTrajectory(300);
  Trajectory est = makeTrajectory(300, 1000.0 + 0.005);  // 5 ms later, same path
  // Keep every second pose: 150 pairs.
  Trajectory sparse;
  for (size_t i = 0; i < est.size(); i += 2) sparse.push_back(est[i]);
  EXPECT_EQ(computeAte(gt, sparse).translation.count, 150);
  // Shifted by 1 s: nothing within 0.02 s... except the overlap, which is associated.
  const Trajectory late = makeTrajectory(300, 1000.0 + 5.0);
  const AteResult ate = computeAte(gt, late);
  EXPECT_EQ(ate.translation.count, 150);
  EXPECT_THROW(computeAte(gt, makeTrajectory(300, 2000.0)), Error);
}

TEST(Rpe, ConstantVelocityAndConstantDrift) {
  // Ground truth moves 1 m/s along x; the estimate moves 1.1 m/s: 0.1 m error per second.
  Trajectory gt, est;
  for (int i = 0; i <= 90; ++i) {
    StampedPose pose;
    pose.timestamp = i / 30.0;
    pose.T_w_c.translation() = Eigen::Vector3d(i / 30.0, 0, 0);
    gt.push_back(pose);
    pose.T_w_c.translation() = Eigen::Vector3d(1.1 * i / 30.0, 0, 0);
    est.push_back(pose);
  }
  RpeOptions options;
  options.delta = 1.0;
  RpeResult rpe = computeRpe(gt, est, options);
  EXPECT_EQ(rpe.translation.count, 61);  // i = 0..60 have a partner 30 frames later
  EXPECT_NEAR(rpe.translation.rmse, 0.1, 1e-9);
  EXPECT_NEAR(rpe.translation.max, 0.1, 1e-9);
  EXPECT_NEAR(rpe.rotation.max, 0.0, 1e-9);
  options.unit = RpeOptions::DeltaUnit::kFrames;
  options.delta = 3;
  rpe = computeRpe(gt, est, options);
  EXPECT_EQ(rpe.translation.count, 88);
  EXPECT_NEAR(rpe.translation.rmse, 0.01, 1e-9);
}

TEST(Rpe, ConstantAngularDriftIsMeasuredInDegrees) {
  // The estimate turns 1 degree per frame more than the ground truth about z, without moving.
  Trajectory gt, est;
  for (int i = 0; i < 20; ++i) {
    StampedPose pose;
    pose.timestamp = i * 0.1;
    gt.push_back(pose);
    pose.T_w_c.linear() = Eigen::AngleAxisd(i * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    est.push_back(pose);
  }
  RpeOptions options;
  options.unit = RpeOptions::DeltaUnit::kFrames;
  options.delta = 2;
  const RpeResult rpe = computeRpe(gt, est, options);
  EXPECT_NEAR(rpe.rotation.mean, 2.0, 1e-9);
  EXPECT_NEAR(rpe.translation.max, 0.0, 1e-12);
}

TEST(Rpe, RigidMisalignmentDoesNotMatter) {
  const Trajectory gt = makeTrajectory(200);
  const RpeResult rpe = computeRpe(gt, transformed(gt, someMisalignment()));
  EXPECT_LT(rpe.translation.max, 1e-9);
  EXPECT_LT(rpe.rotation.max, 1e-6);
}

}  // namespace
}  // namespace pf2
