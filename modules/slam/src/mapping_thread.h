#pragma once
// The mapper's thread (private to modules/slam): keyframes, and frames fused in between, go into
// the Mapper in a thread of their own, which follows the pose graph's corrections.
//
// Thread safety: push(), finish(), stop() and moveTo() from the front end's thread; the Mapper is
// touched only by the mapping thread until stop() (or, synchronous, only inside push()).
#include <exception>
#include <map>
#include <thread>
#include <utility>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"
#include "pf2/core/stage_timer.h"
#include "pf2/core/work_queue.h"
#include "pf2/registration/keyframe.h"
#include "pf2/surface/mapper.h"

namespace pf2 {

// A frame for the map: a keyframe, or a frame fused in between (fuse_every) that hangs off its
// keyframe like a trajectory pose, so pose-graph corrections move it too.
struct FusionJob {
  int id;          // the keyframe id, or kFusedFrameIds + frame index for an in-between frame
  int keyframe_id;
  Eigen::Isometry3d T_k_c;
  cv::Mat static_depth;
  cv::Mat rgb;
  CameraIntrinsics K;
  Eigen::Isometry3d T_w_c;
};

inline constexpr int kFusedFrameIds = 1 << 24;  // above any keyframe id

// Map poses of everything fused so far, from the keyframes' current poses.
inline std::map<int, Eigen::Isometry3d> fusedPoses(const std::map<int, Eigen::Isometry3d>& keyframe_poses,
                                            const std::map<int, std::pair<int, Eigen::Isometry3d>>& anchors) {
  std::map<int, Eigen::Isometry3d> poses;
  for (const auto& [id, anchor] : anchors) {
    const auto keyframe = keyframe_poses.find(anchor.first);
    if (keyframe != keyframe_poses.end()) poses[id] = keyframe->second * anchor.second;
  }
  return poses;
}

// Fuses keyframes (and in-between frames) into the map in its own thread and follows the pose
// graph's corrections. Only that thread touches the Mapper until stop().
class MappingThread {
 public:
  // synchronous: no thread of its own; push() fuses at once in the caller's thread, so the map does
  // not depend on how the threads were scheduled (the same map on every run; slower).
  MappingThread(Mapper* mapper, const KeyframeMap* keyframes, StageStats* stats, bool synchronous)
      : mapper_(mapper), keyframes_(keyframes), stats_(stats), synchronous_(synchronous) {
    if (!synchronous_) thread_ = std::thread([this] { fuse(); });
  }
  ~MappingThread() { stop(); }
  void push(FusionJob job) {
    if (synchronous_) {
      fuseOne(job);
    } else {
      jobs_.push(std::move(job));
    }
  }
  // Waits for the queue to drain; rethrows the mapper's error, if any.
  void finish() {
    stop();
    if (error_) std::rethrow_exception(error_);
  }
  void stop() {
    jobs_.close();
    if (thread_.joinable()) thread_.join();
  }
  // Moves every fused frame to its keyframe's pose in `keyframe_poses`. After finish() only.
  void moveTo(const std::map<int, Eigen::Isometry3d>& keyframe_poses) {
    mapper_->updateKeyframePoses(fusedPoses(keyframe_poses, anchors_));
  }

 private:
  void fuse() {
    try {
      while (auto job = jobs_.pop()) fuseOne(*job);
    } catch (...) {
      error_ = std::current_exception();
      while (jobs_.pop()) {
      }
    }
  }
  // One frame into the map; then, if the pose graph moved keyframes since, everything fused so far
  // follows them.
  void fuseOne(const FusionJob& job) {
    ScopedStageTimer timer(stats_, "map");
    anchors_[job.id] = {job.keyframe_id, job.T_k_c};
    mapper_->addKeyframe(job.id, job.static_depth, job.rgb, job.K, job.T_w_c);
    const uint64_t revision = keyframes_->revision();
    if (revision != revision_seen_) {
      revision_seen_ = revision;
      moveTo(keyframes_->poses());
    }
  }

  Mapper* mapper_;
  const KeyframeMap* keyframes_;
  StageStats* stats_;
  const bool synchronous_;
  WorkQueue<FusionJob> jobs_{64};
  std::map<int, std::pair<int, Eigen::Isometry3d>> anchors_;  // fused id -> (keyframe id, T_k_c)
  uint64_t revision_seen_ = 0;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace pf2
