#pragma once
// BodyTrackFitter: fits the body model to each tracked person (paper §III-C) in a thread of its
// own, so body fitting never holds up camera tracking. The front end offers observations (a
// person's keypoints and depth in one frame, with the track id the human tracker gave); the fitter
// takes one per track every `fit_every` frames into a bounded queue and drops what does not fit in
// it (a skipped fit is interpolated later, BodyTrackAssembler). Per track it keeps:
//   - a warm start: the track's previous fit, moved into the new camera frame by the camera's
//     motion (as tracked then and now), when it is at most warm_start_gap old and its pelvis lies
//     within max_start_depth_gap of the person's measured depth;
//   - the shape: fitted freely for the first shape_fits fits of a track, then held at their
//     mean (a person's shape does not change; one shape per track, fitted once);
//   - the temporal term: later fits are pulled towards the warm start's pose.
// Fits are in the camera frame with the frame's keyframe anchor, so the world placement (eq. 4)
// can use the loop-corrected poses at the end.
//
// Thread safety: offer(), wants() and finish() from one thread (the front end); the fits run in the
// fitter's own thread (or in offer() itself with Options::asynchronous false, for repeatable runs).
#include <array>
#include <functional>
#include <map>
#include <memory>
#include <thread>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/body/body_fitter.h"
#include "pf2/body/body_model.h"
#include "pf2/core/camera_intrinsics.h"
#include "pf2/core/stage_timer.h"
#include "pf2/core/work_queue.h"

namespace pf2 {

// One person in one frame, as the front end saw them.
struct BodyObservation {
  int track_id = 0;
  int frame_index = 0;
  double timestamp = 0;
  std::array<BodyKeypoint, kCocoKeypointCount> keypoints;  // COCO-17, pixels
  // CV_32F metres: the person's depth D_h^t on depth_area (the image region it covers), may be
  // empty; the whole-frame image the fitter needs is made in the fitting thread.
  cv::Mat depth;
  cv::Rect depth_area;
  // CV_8UC3 BGR: the image around the person, for Options::refine_keypoints (may be empty), its
  // top-left corner in the frame, and the person's box in the frame (pixels).
  cv::Mat colour;
  cv::Point colour_origin;
  cv::Rect2f box;
  CameraIntrinsics intrinsics;
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();  // as tracked now
  // The world's up (unit, against gravity) as known now: the fit's upright prior and initial
  // orientation (UpDirectionEstimator; the first camera's -y when the world is its frame).
  Eigen::Vector3d up_w = Eigen::Vector3d(0, -1, 0);
  int keyframe_id = -1;        // the frame's keyframe and pose relative to it, for the final placement
  Eigen::Isometry3d T_k_c = Eigen::Isometry3d::Identity();
};

// A valid fit, in the camera frame of its frame.
struct BodyTrackFit {
  int track_id = 0;
  int frame_index = 0;
  double timestamp = 0;
  int keyframe_id = -1;
  Eigen::Isometry3d T_k_c = Eigen::Isometry3d::Identity();
  BodyParameters body_c;
  double cost = 0;
};

// The longest of a pose's body segments (shoulder and hip widths, torso sides, upper and lower
// limbs) whose two keypoints have at least min_confidence, in metres on the plane `depth` metres in
// front of camera K; 0 when no segment has both ends. Thread safe.
double longestBodySegment(const std::array<BodyKeypoint, kCocoKeypointCount>& keypoints, double depth,
                          const CameraIntrinsics& K, double min_confidence);

// The shorter of a pose's two torso sides (shoulder to hip of one side) whose two keypoints have
// at least min_confidence and lie in the image, more than edge_band pixels inside its edges, in
// metres on the plane `depth` metres in front of camera K; 0 when neither side is seen so.
// Thread safe.
double shortestTorsoSide(const std::array<BodyKeypoint, kCocoKeypointCount>& keypoints, double depth,
                         const CameraIntrinsics& K, double min_confidence, double edge_band);

class BodyTrackFitter {
 public:
  struct Options {
    int fit_every = 3;             // frames between two fits of one track (1 = every frame), [1, 300]
    int queue_capacity = 6;        // observations waiting; more are dropped, [1, 1000]
    int shape_fits = 5;            // fits of a track with a free shape before it is held, [1, 1000]
    double warm_start_gap = 0.5;   // s: an older previous fit is not a start, [0, 10]
    // m: a start whose pelvis lies farther in depth from the median depth of the person's points
    // is not used (the fit starts afresh), [0, 10]; 0 = no check.
    double max_start_depth_gap = 0.3;
    // m: a pose (after the closer look) whose longest body segment (longestBodySegment) measures
    // less at the median depth of the person's points is not fitted, [0, 2]; 0 = no check. A torso
    // side is about 0.5 m, so such a pose is someone farther away seen beside or through this
    // person, whose mask took it (pf2_synth: a person 0.7 m from the lens, cut at the top and the
    // bottom, given the pose of the person seated behind them, measured 0.07-0.10 m there; their
    // fits put the pelvis 0.3-0.4 m off).
    double min_pose_size = 0.15;
    // m: a pose with a torso side in full view (shortestTorsoSide, the fitter's confidence and
    // edge band) shorter than this at the median depth of the person's points is not fitted,
    // [0, 2]; 0 = no check. Between COCO's shoulder and hip a torso side measures about 0.45 m.
    // MoveNet, given a person close to the lens and cut by the border, puts a whole body's
    // keypoints on the part in view: on pf2_synth a person at 1 m walking out of the view's
    // corner, a fifth of them in view, had sides of 0.17 m and fits 30 cm off for a second, the
    // visible part taken for a whole body at half the size. 0.35 also drops fits of people seen
    // whole (their sides, foreshortened, measure 0.3-0.4 m): docs/BENCHMARKS.md.
    double min_torso_side = 0.3;
    double weight_temporal = 1.0;  // pull towards the warm start's pose (BodyFitter::Options), [0, 100]
    bool asynchronous = true;      // false: fit inside offer() (slower; the same fits on every run)
    // Optional: a closer look at the keypoints before each fit (e.g. PoseRefiner). Called in the
    // fitting thread only, one call at a time, with an observation's colour and the person's box
    // in its pixels, and the observation's keypoints moved into those pixels; gives the refined
    // keypoints there, or false to keep the observation's.
    std::function<bool(const cv::Mat& colour, const cv::Rect2f& box,
                       std::array<BodyKeypoint, kCocoKeypointCount>* keypoints)>
        refine_keypoints;
    BodyFitter::Options fitter;
  };

  // The model must outlive the fitter. The ranges of the options are checked where they are
  // declared as settings (bodies.* in slamSettings).
  BodyTrackFitter(const BodyModel& model, const Options& options);
  ~BodyTrackFitter();

  // True when the track is due for a fit at this frame (cheap; call before preparing an observation).
  bool wants(int track_id, int frame_index) const;
  // Queues the observation; false when it was dropped (queue full). Never waits for a fit.
  bool offer(BodyObservation observation);
  // Waits for the queued fits and returns every valid fit, by track then time. Rethrows an error
  // of the fitting thread. Call once; offer() may not be called after it.
  std::vector<BodyTrackFit> finish();

  int offered() const { return offered_; }
  int dropped() const { return dropped_; }
  // Wall-clock time of each fit's steps in the fitting thread: "refine" (the closer look at the
  // keypoints, when there is one) and "fit" (BodyFitter::fit). Read it after finish().
  const StageStats& stats() const { return stats_; }

 private:
  struct TrackState;
  void run();
  void fitOne(const BodyObservation& observation);
  BodyFitInput fitInput(const BodyObservation& observation, const TrackState& track, BodyParameters* start);
  // Whether a warm start's pelvis lies within max_start_depth_gap of the points' median depth.
  bool startsNearThePerson(const BodyParameters& start, const std::vector<Eigen::Vector3d>& points_c) const;
  // Whether the input's keypoints measure at least min_pose_size, and their torso sides in view at
  // least min_torso_side, at its points' median depth.
  bool poseFitsTheDepth(const BodyFitInput& input, const CameraIntrinsics& K) const;

  const BodyModel& model_;
  const Options options_;
  BodyFitter fitter_;
  BodyFitter fixed_shape_fitter_;  // the same with the shape held
  WorkQueue<BodyObservation> queue_;
  std::map<int, int> last_offered_;             // track id -> frame index (front end only)
  std::map<int, TrackState> tracks_;            // fitting thread only
  std::vector<BodyTrackFit> fits_;              // fitting thread only until finish()
  std::exception_ptr error_;
  int offered_ = 0, dropped_ = 0;
  bool finished_ = false;
  StageStats stats_;
  std::thread thread_;
};

}  // namespace pf2
