#include "pf2/registration/keyframe.h"

#include "pf2/core/error.h"
#include "pf2/core/pose.h"

namespace pf2 {

Keyframe makeKeyframe(const OdometryFrame& frame) {
  if (frame.levels.empty() || !frame.has_features)
    throw Error("makeKeyframe: frame " + std::to_string(frame.index) + " has no features");
  Keyframe k;
  k.frame_index = frame.index;
  k.timestamp = frame.timestamp;
  k.intrinsics = frame.levels[0].intrinsics;
  k.gray = frame.gray;
  frame.levels[0].depth.convertTo(k.depth, CV_16U, Keyframe::kDepthUnitsPerMetre);
  k.keypoints = frame.keypoints;
  k.descriptors = frame.descriptors;
  k.keypoint_points = frame.keypoint_points;
  return k;
}

int KeyframeMap::add(Keyframe keyframe, const Eigen::Isometry3d& T_w_k) {
  std::lock_guard<std::mutex> lock(mutex_);
  keyframe.id = static_cast<int>(keyframes_.size());
  keyframes_.push_back(std::make_shared<const Keyframe>(std::move(keyframe)));
  poses_.push_back(T_w_k);
  return keyframes_.back()->id;
}

int KeyframeMap::addRelative(Keyframe keyframe, int reference_id, const Eigen::Isometry3d& T_ref_k) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (reference_id < 0 || reference_id >= static_cast<int>(poses_.size()))
    throw Error("KeyframeMap: no keyframe " + std::to_string(reference_id));
  keyframe.id = static_cast<int>(keyframes_.size());
  keyframes_.push_back(std::make_shared<const Keyframe>(std::move(keyframe)));
  poses_.push_back(poses_[reference_id] * T_ref_k);
  return keyframes_.back()->id;
}

size_t KeyframeMap::size() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return keyframes_.size();
}

std::shared_ptr<const Keyframe> KeyframeMap::keyframe(int id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (id < 0 || id >= static_cast<int>(keyframes_.size()))
    throw Error("KeyframeMap: no keyframe " + std::to_string(id));
  return keyframes_[id];
}

Eigen::Isometry3d KeyframeMap::pose(int id) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (id < 0 || id >= static_cast<int>(poses_.size()))
    throw Error("KeyframeMap: no keyframe " + std::to_string(id));
  return poses_[id];
}

std::map<int, Eigen::Isometry3d> KeyframeMap::poses() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::map<int, Eigen::Isometry3d> out;
  for (size_t i = 0; i < poses_.size(); ++i) out.emplace(static_cast<int>(i), poses_[i]);
  return out;
}

void KeyframeMap::updatePoses(const std::map<int, Eigen::Isometry3d>& T_w_k) {
  std::lock_guard<std::mutex> lock(mutex_);
  const int n = static_cast<int>(poses_.size());
  int newest = -1;
  Eigen::Isometry3d T_new_old = Eigen::Isometry3d::Identity();  // world correction of `newest`
  for (const auto& [id, pose] : T_w_k) {
    if (id < 0 || id >= n) continue;
    if (id > newest) {
      newest = id;
      T_new_old = pose * poses_[id].inverse();
    }
    poses_[id] = pose;
  }
  if (newest >= 0)
    for (int id = newest + 1; id < n; ++id)
      if (!T_w_k.count(id)) poses_[id] = T_new_old * poses_[id];
  ++revision_;
}

uint64_t KeyframeMap::revision() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return revision_;
}

KeyframeSelector::KeyframeSelector() : KeyframeSelector(Options()) {}
KeyframeSelector::KeyframeSelector(const Options& options) : options_(options) {}

bool KeyframeSelector::needsKeyframe(const Eigen::Isometry3d& T_k_c, double inlier_ratio,
                                     int frames_since_keyframe) const {
  if (T_k_c.translation().norm() > options_.max_translation) return true;
  if (rotationAngle(T_k_c.rotation()) > options_.max_rotation) return true;
  if (inlier_ratio < options_.min_inlier_ratio) return true;
  return options_.max_frames > 0 && frames_since_keyframe >= options_.max_frames;
}

}  // namespace pf2
