#include "pf2/slam/motion_guess.h"

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

Eigen::Isometry3d moved(double x, double y, double z, double yaw = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(x, y, z);
  return T;
}

double distance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.matrix() - b.matrix()).norm();
}

// Keyframe 0 at the origin, keyframe 1 30 cm along x.
void addTwoKeyframes(KeyframeMap* map) {
  map->add(Keyframe(), Eigen::Isometry3d::Identity());
  map->add(Keyframe(), moved(0.3, 0.0, 0.0));
}

// The guess repeats the last motion from the last pose: 2 cm per frame along x, 0.01 rad of yaw.
TEST(MotionGuess, RepeatsTheLastMotion) {
  KeyframeMap map;
  addTwoKeyframes(&map);
  MotionGuess guess;
  EXPECT_FALSE(guess.known());
  guess.posed(0, moved(0.10, 0, 0, 0.00));
  EXPECT_TRUE(guess.known());
  EXPECT_LT(distance(guess.motion(map), Eigen::Isometry3d::Identity()), 1e-12);  // one pose: no motion yet
  guess.posed(0, moved(0.12, 0, 0, 0.01));
  const Eigen::Isometry3d next = guess.lastPose(map) * guess.motion(map).inverse();
  EXPECT_LT(distance(next, moved(0.12, 0, 0, 0.01) * moved(0.10, 0, 0, 0.00).inverse() * moved(0.12, 0, 0, 0.01)),
            1e-12);
  guess.lost();
  EXPECT_FALSE(guess.known());
}

// A pose-graph correction between two frames moves the keyframes: the last pose follows its
// keyframe, and the motion between the last two frames stays what tracking measured, also across
// a change of keyframe (the poses in the world, kept as they were, would jump by the correction).
TEST(MotionGuess, FollowsTheKeyframesThroughACorrection) {
  KeyframeMap map;
  addTwoKeyframes(&map);
  MotionGuess guess;
  guess.posed(0, moved(0.28, 0, 0));       // on keyframe 0, 28 cm along x
  guess.posed(1, moved(0.0, 0, 0, 0.02));  // on keyframe 1 (at x = 30 cm), turned 0.02 rad
  const Eigen::Isometry3d motion_before = guess.motion(map);
  // The back end moves keyframe 1 by 4 cm and a little turn, keyframe 0 stays.
  const Eigen::Isometry3d corrected = moved(0.34, 0.0, 0.0, 0.01);
  map.updatePoses({{0, Eigen::Isometry3d::Identity()}, {1, corrected}});
  EXPECT_LT(distance(guess.lastPose(map), corrected * moved(0.0, 0, 0, 0.02)), 1e-12);
  // The motion is now measured between the corrected keyframes: the second frame is 6 cm ahead of
  // the first instead of 2, which is what the corrected map says.
  const Eigen::Isometry3d expected = (corrected * moved(0.0, 0, 0, 0.02)).inverse() * moved(0.28, 0, 0);
  EXPECT_LT(distance(guess.motion(map), expected), 1e-12);
  EXPECT_GT(distance(guess.motion(map), motion_before), 0.03);
  // Both on the same keyframe: a correction of that keyframe leaves the motion as it was.
  MotionGuess same;
  same.posed(1, moved(0.00, 0, 0));
  same.posed(1, moved(0.02, 0, 0));
  const Eigen::Isometry3d same_before = same.motion(map);
  map.updatePoses({{1, moved(0.40, 0.1, 0.0, 0.05)}});
  EXPECT_LT(distance(same.motion(map), same_before), 1e-12);
  EXPECT_LT(distance(same.lastPose(map), moved(0.40, 0.1, 0.0, 0.05) * moved(0.02, 0, 0)), 1e-12);
}

TEST(MotionGuess, AnUnknownKeyframeIsAnError) {
  KeyframeMap map;
  addTwoKeyframes(&map);
  MotionGuess guess;
  guess.posed(7, Eigen::Isometry3d::Identity());
  EXPECT_THROW(guess.lastPose(map), Error);
}

}  // namespace
}  // namespace pf2
