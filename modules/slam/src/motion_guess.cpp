#include "pf2/slam/motion_guess.h"

namespace pf2 {

void MotionGuess::posed(int keyframe_id, const Eigen::Isometry3d& T_k_c) {
  before_last_ = last_;
  last_ = {keyframe_id, T_k_c};
  ++poses_in_row_;
}

Eigen::Isometry3d MotionGuess::lastPose(const KeyframeMap& keyframes) const {
  return keyframes.pose(last_.keyframe_id) * last_.T_k_c;
}

Eigen::Isometry3d MotionGuess::motion(const KeyframeMap& keyframes) const {
  if (poses_in_row_ < 2) return Eigen::Isometry3d::Identity();
  const Eigen::Isometry3d T_w_before = keyframes.pose(before_last_.keyframe_id) * before_last_.T_k_c;
  return lastPose(keyframes).inverse() * T_w_before;
}

}  // namespace pf2
