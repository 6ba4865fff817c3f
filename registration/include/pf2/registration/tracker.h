#pragma once
// Camera tracking facade: frame-to-keyframe RGB-D odometry on human-free depth, keyframe
// selection, relocalisation when tracking is lost, and the pose-graph back-end with loop closing.
//
//   Tracker tracker(Tracker::Options{});
//   for (...) {
//     const TrackResult r = tracker.track(frame, person_mask);  // mask may be empty
//     if (hasPose(r.status)) use(r.T_w_c);                         // a lost frame has no pose
//   }
//   tracker.finish();  // let the back-end finish its queue; keyframes() then holds final poses
//
// The world frame is the first frame with enough usable depth. Status of a frame:
//   kOk          an alignment was measured and passed the checks: against the current keyframe
//                from the motion prior (or the ORB fallback), or, when that fails, against the
//                previous measured frame (frame-to-frame, chained onto its keyframe pose);
//   kBridged     no alignment held (a person covering the view, blur, a rejected jump) but the
//                last measured pose is at most max_bridged_frames frames old: the frame gets the
//                motion prior's pose (constant velocity, damped), never fused into a map;
//   kRelocalised the odometry was not valid and the frame was matched without a prior against
//                the keyframes (the last one + appearance candidates) with at least
//                min_relocalisation_inlier_ratio, or with less overlap but confirmed by the
//                keyframe aligned back onto it (PoseGraphBackend::agreesBothWays). Relocalised
//                frames can occur without any lost
//                frame;
//   kLost        no pose: before the first usable frame, or after max_bridged_frames bridged
//                frames in a row until relocalisation succeeds. Never given an invented pose.
//
// Divergence guard: a measured pose (kOk) must be physically reachable: from the last measured
// pose at most max_speed (max_angular_speed) times the time since then, plus a tolerance; and
// from the constant-velocity prediction at most what max_acceleration allows over that time, plus
// a tolerance for the prediction's own error. A rejected pose never becomes the frame's pose; the
// frame is bridged instead. Only relocalisation (a match without any prior, verified as above)
// can place a frame beyond that reach.
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
#include "pf2/registration/reference_cleaner.h"
#include "pf2/registration/rgbd_odometry.h"

namespace pf2 {

enum class TrackStatus { kOk, kBridged, kLost, kRelocalised };
// "tracked" | "bridged" | "lost" | "relocalised"
const char* toString(TrackStatus status);
// True for every status but kLost.
inline bool hasPose(TrackStatus status) { return status != TrackStatus::kLost; }

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
    // The back end's `verification` odometry is replaced by `odometry`: loops and local edges are
    // measured with the tracking camera's settings (lens distortion, depth range).
    PoseGraphBackend::Options backend;
    // Points of the current keyframe that later frames see through are taken out of it.
    ReferenceCleaner::Options cleaning;
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
    // A keyframe is made only from a frame whose alignment was well conditioned (largest /
    // smallest eigenvalue of its normal matrix at most this): a view left with a wall and little
    // else once people are removed slides along the wall, and as a keyframe it would anchor that
    // error (typical good views: 1e3 - 5e3 on TUM and Bonn frames).
    double max_keyframe_condition = 2e4;
    // Below this fraction of pixels with usable depth a frame is kLost: the few static pixels
    // left do not constrain the pose (a synthetic 900-frame loop had a frame with 3.5 % depth
    // tracked 42 cm off).
    double min_tracking_depth_fraction = 0.05;
    // An alignment to the keyframe is only accepted when at least this share of its associated
    // points are inliers: a pose pulled off by what is left of people, or by a view that people
    // crowd, fits less and less of what it associates (good alignments on the Bonn crowd frames:
    // 0.85-0.95; the one that started the camera's loss there: 0.53), and the frame-to-frame
    // fallback is tried instead. 0 = no check.
    double min_tracking_agreement = 0.5;
    // Relocalisation (no motion prior to confirm the pose) needs this dense inlier ratio;
    // tracking accepts RgbdOdometry::Options::min_inlier_ratio (0.35).
    double min_relocalisation_inlier_ratio = 0.6;
    // Frames in a row that may be bridged with the motion prior's pose (about half a second at
    // 30 Hz); the next one is kLost. 0 = no bridging (a failed frame is lost at once).
    int max_bridged_frames = 15;
    // Each bridged frame keeps this fraction of the last inter-frame motion (1 = constant
    // velocity): the prior's velocity is a noisy two-frame estimate, so it is faded out fast.
    double bridge_motion_decay = 0.5;
    // Divergence guard (see the header comment): speeds and accelerations of a hand-held or
    // robot-mounted camera; tolerances cover the noise of one frame's pose and velocity.
    double max_speed = 2.0;                 // m/s
    double max_angular_speed = 4.0;         // rad/s
    double max_acceleration = 15.0;         // m/s^2
    double max_angular_acceleration = 40.0; // rad/s^2
    double guard_tolerance_translation = 0.04;  // metres
    double guard_tolerance_rotation = 0.08;     // radians
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
  // Odometry against the keyframe from the motion prior, then (if that fails) from the last
  // pose; sets T_k_c_ when a result is valid and passes the divergence guard.
  bool alignToKeyframe(OdometryFrame* current, const Eigen::Isometry3d& T_k_prior, double timestamp,
                       TrackResult* result);
  // Odometry against the previous measured frame (more overlap than the keyframe after fast
  // motion); the pose is chained onto that frame's pose relative to the keyframe.
  bool alignToPreviousFrame(OdometryFrame* current, const Eigen::Isometry3d& T_k_prior,
                            double timestamp, TrackResult* result);
  bool relocalise(OdometryFrame* frame, TrackResult* result);
  // Inliers per associated point at least min_tracking_agreement.
  bool consistent(const DenseAlignment& alignment) const;
  // The divergence guard: is T_k_c reachable from the last measured pose and the prior, given
  // the time since the last measured pose?
  bool withinReach(const Eigen::Isometry3d& T_k_c, const Eigen::Isometry3d& T_k_prior,
                          double timestamp) const;
  // Bookkeeping after a frame got a pose (measured or bridged).
  void keepFrame(OdometryFrame* current, bool measured, double timestamp);

  Options options_;
  RgbdOdometry odometry_;
  KeyframeSelector selector_;
  KeyframeMap map_;
  LoopDetector loops_;
  ReferenceCleaner cleaner_;
  std::unique_ptr<PoseGraphBackend> backend_;
  StageStats stats_;

  bool initialised_ = false;
  bool lost_ = false;
  OdometryFrame reference_;  // the current keyframe, prepared as a reference
  int reference_id_ = -1;
  Eigen::Isometry3d T_k_c_ = Eigen::Isometry3d::Identity();       // last tracked pose
  Eigen::Isometry3d T_prev_cur_ = Eigen::Isometry3d::Identity();  // last inter-frame motion
  int frames_since_keyframe_ = 0;
  int bridged_in_row_ = 0;
  double last_measured_timestamp_ = 0.0;
  Eigen::Isometry3d T_k_measured_ = Eigen::Isometry3d::Identity();  // last measured pose
  // The previous frame if its pose was measured (empty levels otherwise), with that pose
  // relative to the current keyframe.
  OdometryFrame previous_;
  Eigen::Isometry3d T_k_previous_ = Eigen::Isometry3d::Identity();
};

}  // namespace pf2
