#pragma once
// Where the next frame is expected, before it is tracked: the last frame's pose moved on by the
// last inter-frame motion (constant velocity). The person filter needs it for the keyframes'
// predicted depth and for the temporal guard's carried person pixels.
//
// Poses are kept as tracking measured them, relative to their keyframes (T_k_c), and placed with
// the keyframes' poses as they are when the guess is asked for. A pose-graph correction that
// arrives between two frames then moves both with their keyframes: the guess neither jumps by the
// correction nor lags behind the corrected keyframes it is compared with. (Kept in the world
// frame, a correction of a few centimetres misplaced the prediction of the next frames; the
// Bonn crowd frames with the back end in the tracker's thread: 2.21 -> 1.79 cm.)
#include <Eigen/Geometry>

#include "pf2/registration/keyframe.h"

namespace pf2 {

class MotionGuess {
 public:
  // A frame got the pose T_k_c relative to keyframe `keyframe_id` (tracked, bridged or
  // relocalised). NOT thread safe.
  void posed(int keyframe_id, const Eigen::Isometry3d& T_k_c);
  // A frame got no pose: the guess starts over.
  void lost() { poses_in_row_ = 0; }

  // Whether there is a last pose to guess from.
  bool known() const { return poses_in_row_ >= 1; }
  // T_w_c of the last posed frame with its keyframe's current pose. Requires known(); throws
  // pf2::Error when the keyframe is not in `keyframes`.
  Eigen::Isometry3d lastPose(const KeyframeMap& keyframes) const;
  // T_cur_prev, the motion from the last posed frame to the next one: the last inter-frame motion
  // (identity with fewer than two poses in a row).
  Eigen::Isometry3d motion(const KeyframeMap& keyframes) const;

 private:
  struct Anchored {
    int keyframe_id = -1;
    Eigen::Isometry3d T_k_c = Eigen::Isometry3d::Identity();
  };
  Anchored last_, before_last_;
  int poses_in_row_ = 0;
};

}  // namespace pf2
