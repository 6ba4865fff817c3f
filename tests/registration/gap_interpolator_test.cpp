#include "pf2/registration/gap_interpolator.h"

#include "pf2/core/pose.h"

#include <cmath>

#include <gtest/gtest.h>

namespace pf2 {
namespace {

// A camera at 30 Hz on a curve (turning about the vertical as it goes): position and rotation at t.
Eigen::Isometry3d truePose(double t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.4 * t, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(std::sin(1.5 * t), 0.05 * t, 1.0 - std::cos(1.5 * t));
  return T;
}

// Frames [gap_begin, gap_end) unmeasured: the first `bridged` of them hold the pose of the frame
// before the gap (the faded motion prior stops the camera), the rest have no pose (lost).
std::vector<RunFrame> runWithGap(int frames, int gap_begin, int gap_end, int bridged) {
  std::vector<RunFrame> run(frames);
  for (int i = 0; i < frames; ++i) {
    run[i].timestamp = i / 30.0;
    run[i].measured = i < gap_begin || i >= gap_end;
    run[i].has_pose = run[i].measured || i < gap_begin + bridged;
    run[i].T_w_c = run[i].measured ? truePose(run[i].timestamp) : truePose((gap_begin - 1) / 30.0);
  }
  return run;
}

double positionError(const RunFrame& frame) {
  return (frame.T_w_c.translation() - truePose(frame.timestamp).translation()).norm();
}

double rotationError(const RunFrame& frame) {
  return rotationAngle(frame.T_w_c.linear().transpose() * truePose(frame.timestamp).linear());
}

TEST(GapInterpolator, FillsBridgedAndLostFramesBetweenMeasuredOnes) {
  std::vector<RunFrame> run = runWithGap(90, 30, 55, 15);  // 25 frames (0.83 s), 10 of them lost
  double worst_before = 0, worst_linear = 0;
  for (int i = 30; i < 45; ++i) worst_before = std::max(worst_before, positionError(run[i]));
  for (int i = 30; i < 55; ++i) {
    RunFrame linear = run[i];
    linear.T_w_c = interpolate(run[29].T_w_c, run[55].T_w_c, (i - 29) / 26.0);
    worst_linear = std::max(worst_linear, positionError(linear));
  }
  const std::vector<size_t> filled = GapInterpolator(GapInterpolator::Options()).fill(&run);
  ASSERT_EQ(filled.size(), 25u);
  EXPECT_EQ(filled.front(), 30u);
  EXPECT_EQ(filled.back(), 54u);
  EXPECT_GT(worst_before, 0.4);   // the held pose: the camera moved 0.5 m meanwhile
  EXPECT_GT(worst_linear, 0.15);  // the chord of a 1.25 rad arc of 1 m radius
  for (int i = 30; i < 55; ++i) {
    EXPECT_TRUE(run[i].has_pose);
    // Hermite with the end velocities measured over the 0.2 s before and after the gap.
    EXPECT_LT(positionError(run[i]), 0.03) << "frame " << i;
    EXPECT_LT(rotationError(run[i]), 0.005) << "frame " << i;  // slerp of a constant turn
  }
  for (int i : {29, 55}) EXPECT_LT(positionError(run[i]), 1e-12);  // the measured ends stay
}

TEST(GapInterpolator, LeavesGapsWithoutTwoMeasuredEndsOrTooLong) {
  // Lost from frame 70 to the end: nothing after the gap bounds it.
  std::vector<RunFrame> open_end = runWithGap(90, 70, 90, 10);
  EXPECT_TRUE(GapInterpolator(GapInterpolator::Options()).fill(&open_end).empty());
  EXPECT_FALSE(open_end[85].has_pose);
  // 4 s between the measured ends: longer than max_gap (3 s).
  std::vector<RunFrame> long_gap = runWithGap(200, 30, 149, 15);
  EXPECT_TRUE(GapInterpolator(GapInterpolator::Options()).fill(&long_gap).empty());
  EXPECT_FALSE(long_gap[100].has_pose);
  // Off.
  GapInterpolator::Options off;
  off.max_gap = 0;
  std::vector<RunFrame> short_gap = runWithGap(90, 30, 40, 5);
  EXPECT_TRUE(GapInterpolator(off).fill(&short_gap).empty());
}

TEST(GapInterpolator, NoEndVelocityAcrossARestart) {
  // At rest at the origin; frame 20 relocalised 1 m away (a restart), measured again at rest there
  // from frame 26 after a gap: the jump into frame 20 is no velocity, so the gap stays between
  // the two ends (no overshoot of 1 m / 33 ms).
  std::vector<RunFrame> run(40);
  for (int i = 0; i < 40; ++i) {
    run[i].timestamp = i / 30.0;
    run[i].measured = run[i].has_pose = i < 21 || i >= 26;
    run[i].restarts = i == 20;
    if (i >= 20) run[i].T_w_c.translation() = Eigen::Vector3d(1.0, 0.0, 0.0);
  }
  ASSERT_EQ(GapInterpolator(GapInterpolator::Options()).fill(&run).size(), 5u);
  for (int i = 21; i < 26; ++i) EXPECT_NEAR(run[i].T_w_c.translation().x(), 1.0, 1e-9) << "frame " << i;
}

TEST(GapInterpolator, OneMeasuredFrameAtAnEndGivesTheMeanVelocity) {
  // Measured frames 0 and 10 only, at rest and 1 m apart: without neighbours to measure the end
  // velocities, the gap is crossed at its mean velocity, i.e. linearly.
  std::vector<RunFrame> run(11);
  for (int i = 0; i <= 10; ++i) {
    run[i].timestamp = i / 30.0;
    run[i].measured = run[i].has_pose = i == 0 || i == 10;
  }
  run[10].T_w_c.translation() = Eigen::Vector3d(1.0, 0.0, 0.0);
  ASSERT_EQ(GapInterpolator(GapInterpolator::Options()).fill(&run).size(), 9u);
  for (int i = 1; i < 10; ++i) EXPECT_NEAR(run[i].T_w_c.translation().x(), i / 10.0, 1e-9);
}

}  // namespace
}  // namespace pf2
