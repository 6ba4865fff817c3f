#pragma once
// Camera tracking facade: frame-to-keyframe RGB-D odometry on human-free depth, keyframe
// selection, relocalisation when tracking is lost, and the pose-graph back-end with loop closing.
//
//   Tracker tracker(Tracker::Options{});
//   for (...) {
//     const TrackResult r = tracker.track(frame, person_mask);  // mask may be empty
//     if (r.status != TrackStatus::kLost) use(r.T_w_c);          // a lost frame has no pose
//   }
//   tracker.finish();  // let the back-end finish its queue; keyframes() then holds final poses
//
// The world frame is the first frame with enough usable depth. Status of a frame:
//   kOk          the odometry against the current keyframe (from the motion prior, or the ORB
//                fallback) is valid;
//   kRelocalised that odometry was not valid (this frame, or every frame since the last lost
//                one), and the frame was matched without a prior against the keyframes (the last
//                one + appearance candidates) with at least min_relocalisation_inlier_ratio. It
//                has a pose. So relocalised frames can occur without any lost frame: a frame
//                where the odometry breaks but relocalisation succeeds is never lost.
//   kLost        no pose: too little depth, or odometry and relocalisation both failed. Never
//                given an invented pose.
//
// The current pose is kept relative to the current keyframe (T_w_c = T_w_k * T_k_c), so pose
// graph corrections reach tracking at once. Thread safety: track() and finish() must be called
// from one thread; keyframes() and backend() are thread safe objects.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/frame.h"
#include "pf2/core/stage_timer.h"
#include "pf2/registration/keyframe.h"
#include "pf2/registration/loop_detector.h"
#include "pf2/registration/pose_graph_backend.h"
#include "pf2/registration/rgbd_odometry.h"

namespace pf2 {

enum class TrackStatus { kOk, kLost, kRelocalised };
const char* toString(TrackStatus status);  // "ok" | "lost" | "relocalised"

struct TrackResult {
  TrackStatus status = TrackStatus::kLost;
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();  // meaningless when lost
  int keyframe_id = -1;            // keyframe the pose is measured from (the new one if created)
  // Pose relative to that keyframe: T_w_c = T_w_k * T_k_c with T_w_k as the map holds it now;
  // after pose-graph corrections, keyframes().pose(keyframe_id) * T_k_c is the corrected pose.
  Eigen::Isometry3d T_k_c = Eigen::Isometry3d::Identity();
  bool keyframe_created = false;   // this frame became a keyframe
  OdometryResult odometry;         // quality of the alignment behind the pose (or the failure)
  std::vector<std::pair<std::string, double>> stage_ms;  // this frame's sub-stage times, ms
};

class Tracker {
 public:
  struct Options {
    RgbdOdometry::Options odometry;
    KeyframeSelector::Options keyframes;
    LoopDetector::Options loops;
    PoseGraphBackend::Options backend;
    // true: the back-end runs in its own thread; false: it runs inside track() right after a
    // keyframe is made (deterministic; tests and single-core use).
    bool asynchronous_backend = true;
    // Keyframes tried per relocalisation attempt besides the last one (appearance best first).
    int relocalisation_candidates = 3;
    // Predict the next pose by repeating the last inter-frame motion (else: no motion).
    bool constant_velocity = true;
    // A keyframe (the first one too) needs at least this fraction of pixels with usable depth;
    // a frame with less (a person covering much of the view) is tracked but keeps the old
    // keyframe, because a keyframe on a sliver of scene anchors later frames and loops badly.
    double min_keyframe_depth_fraction = 0.2;
    // Below this fraction of pixels with usable depth a frame is kLost: the few static pixels
    // left do not constrain the pose (a synthetic 900-frame loop had a frame with 3.5 % depth
    // tracked 42 cm off).
    double min_tracking_depth_fraction = 0.05;
    // Relocalisation (no motion prior to confirm the pose) needs this dense inlier ratio;
    // tracking accepts RgbdOdometry::Options::min_inlier_ratio (0.35).
    double min_relocalisation_inlier_ratio = 0.6;
  };

  explicit Tracker(const Options& options);
  ~Tracker();
  Tracker(const Tracker&) = delete;
  Tracker& operator=(const Tracker&) = delete;

  // Tracks one frame (depth with people already removed; person_mask: empty or CV_8U, 255 =
  // person, also kept out of colour and features). Throws pf2::Error on malformed images.
  TrackResult track(const Frame& frame, const cv::Mat& person_mask = cv::Mat());
  // Waits until the back-end has processed every keyframe made so far.
  void finish();

  const Options& options() const { return options_; }
  KeyframeMap& keyframes() { return map_; }
  const KeyframeMap& keyframes() const { return map_; }
  PoseGraphBackend& backend() { return *backend_; }
  // Per-sub-stage timing of all frames: prepare, odometry, keyframe, relocalise, backend.
  const StageStats& stats() const { return stats_; }

 private:
  // The first keyframe defines the world; later ones are placed relative to reference_id_.
  void createKeyframe(OdometryFrame* frame, TrackResult* result);
  bool relocalise(OdometryFrame* frame, TrackResult* result);

  Options options_;
  RgbdOdometry odometry_;
  KeyframeSelector selector_;
  KeyframeMap map_;
  LoopDetector loops_;
  std::unique_ptr<PoseGraphBackend> backend_;
  StageStats stats_;

  bool initialised_ = false;
  bool lost_ = false;
  OdometryFrame reference_;  // the current keyframe, prepared as a reference
  int reference_id_ = -1;
  Eigen::Isometry3d T_k_c_ = Eigen::Isometry3d::Identity();       // last tracked pose
  Eigen::Isometry3d T_prev_cur_ = Eigen::Isometry3d::Identity();  // last inter-frame motion
  int frames_since_keyframe_ = 0;
};

}  // namespace pf2
