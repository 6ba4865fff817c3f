#pragma once
// The mapper's thread (private to modules/slam): keyframes, and frames fused in between, go into
// the Mapper in a thread of their own; the pose graph's corrections reach the map after every
// correction (follow_corrections) or once, at the end of the run (moveTo).
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

// Fuses keyframes (and in-between frames) into the map in its own thread. Only that thread
// touches the Mapper until stop().
//
// Why the corrections may wait for the end: the back end moves the same keyframes again and again
// (a growing drift correction: 61 re-fusions of 38 fused frames in the 150 Bonn crowd frames,
// against 24 at the end), each a de-integration and an integration, while nothing reads the map
// before the run ends. The re-fusion is exact, so the final map is the same either way within the
// Mapper's 1 mm / 1 mrad tolerance; a frame the Mapper is about to drop (max_stored_keyframes)
// still goes to its current pose first.
class MappingThread {
 public:
  // synchronous: no thread of its own; push() fuses at once in the caller's thread, so the map does
  // not depend on how the threads were scheduled (the same map on every run; slower).
  // follow_corrections: re-fuse after every pose-graph correction, not only in moveTo().
  MappingThread(Mapper* mapper, const KeyframeMap* keyframes, StageStats* stats, bool synchronous,
                bool follow_corrections)
      : mapper_(mapper), keyframes_(keyframes), stats_(stats), synchronous_(synchronous),
        follow_corrections_(follow_corrections) {
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
  // One frame into the map; then, when following corrections and the pose graph moved keyframes
  // since, everything fused so far follows them.
  void fuseOne(const FusionJob& job) {
    ScopedStageTimer timer(stats_, "map");
    anchors_[job.id] = {job.keyframe_id, job.T_k_c};
    if (!follow_corrections_) placeBeforeDropping();
    mapper_->addKeyframe(job.id, job.static_depth, job.rgb, job.K, job.T_w_c);
    if (!follow_corrections_) return;
    const uint64_t revision = keyframes_->revision();
    if (revision != revision_seen_) {
      revision_seen_ = revision;
      moveTo(keyframes_->poses());
    }
  }

  // The frame the Mapper drops next freezes where it is: it goes to its current pose first.
  void placeBeforeDropping() {
    const int id = mapper_->nextToDrop();
    const auto anchor = anchors_.find(id);
    if (anchor == anchors_.end()) return;
    mapper_->updateKeyframePoses(fusedPoses(keyframes_->poses(), {{id, anchor->second}}));
  }

  Mapper* mapper_;
  const KeyframeMap* keyframes_;
  StageStats* stats_;
  const bool synchronous_;
  const bool follow_corrections_;
  WorkQueue<FusionJob> jobs_{64};
  std::map<int, std::pair<int, Eigen::Isometry3d>> anchors_;  // fused id -> (keyframe id, T_k_c)
  uint64_t revision_seen_ = 0;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace pf2
