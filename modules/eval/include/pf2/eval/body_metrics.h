#pragma once
// Body accuracy against pf2_synth's ground truth: the mean per-joint position error (MPJPE) of
// fitted bodies (humans.json) against gt/joints.txt, per body frame matched to the true person
// whose pelvis is nearest (within a distance), and the median error of each joint.
#include <array>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "pf2/body/body_model.h"
#include "pf2/eval/error_statistics.h"
#include "pf2/humans/body_tracks.h"

namespace pf2 {

using BodyJoints = std::array<Eigen::Vector3d, kBodyJointCount>;

// Key of a person in a frame: (timestamp in microseconds, id).
using PersonFrameKey = std::pair<long long, int>;
long long timestampMicros(double timestamp);

// Reads gt/joints.txt (`timestamp id j0x j0y j0z ... j23x j23y j23z`). Throws pf2::Error
// "path:line: ..." on a malformed line, naming the file when it is missing. Thread safe.
std::map<PersonFrameKey, BodyJoints> readGroundTruthJoints(const std::string& path);

struct BodyMetrics {
  int body_frames = 0;       // body frames scored (matched to a true person)
  int unmatched = 0;         // body frames with no true person within the distance
  ErrorStatistics mpjpe;     // metres, over all matched body frames (fitted or not)
  ErrorStatistics mpjpe_fitted;  // ... over frames with a fit of their own
  std::array<double, kBodyJointCount> joint_median{};  // metres, per joint, over all matched frames
};

// Scores `bodies` (moved by T_gt_est into the ground truth's frame) against `truth`, each body
// frame against the person whose pelvis (joint 0) is nearest at that timestamp, when within
// match_distance metres. Thread safe.
BodyMetrics evaluateBodies(const std::vector<BodyTrack>& bodies, const Eigen::Isometry3d& T_gt_est,
                           const std::map<PersonFrameKey, BodyJoints>& truth, double match_distance);

}  // namespace pf2
