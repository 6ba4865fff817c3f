#pragma once
// The pipeline of DESIGN.md: frames -> person detector -> Dual-BBox filter -> tracker -> mapper,
// and the human tracker on the filter's people once the frame's pose is known.
//
// Threads: run() (through SlamRunner) decodes frames ahead in a loader thread and detects the
// people of the next frame in a detection thread while the calling thread filters and tracks this
// one, then associates the people's centres (microseconds); the tracker's pose-graph back end
// (loop closure) runs in its own thread; a mapper thread fuses keyframes into the TSDF/OctoMap and
// re-fuses them when the pose graph moves them; a body thread fits the people's bodies. Only the
// detection thread touches the detector; only the front end the filter, tracker and human
// tracker; only the mapper thread the Mapper; only the body thread the body fitter's state.
#include <functional>
#include <memory>
#include <string>

#include "pf2/core/frame_source.h"
#include "pf2/core/pose.h"
#include "pf2/core/stage_timer.h"
#include "pf2/humans/body_tracks.h"
#include "pf2/humans/human_track.h"
#include "pf2/registration/tracker.h"
#include "pf2/slam/scene_export.h"
#include "pf2/slam/slam_options.h"

namespace pf2 {

struct SlamRunSummary {
  int frames = 0;        // frames processed
  int tracked = 0;       // frames with a pose (tracked, bridged or relocalised)
  int lost = 0;          // frames without a pose
  int relocalised = 0;   // frames where tracking came back
  int bridged = 0;       // frames given the motion prior's pose (no alignment held)
  int interpolated = 0;  // of the bridged ones: posed at the end of the run between two measured
                         // frames (GapInterpolator) instead of by the motion prior or not at all
  int keyframes = 0;
  int loop_closures = 0; // verified loop edges in the keyframe pose graph
  int local_edges = 0;   // verified edges between near keyframes (the back end's local window)
  int map_refusions = 0; // fused frames re-fused because the pose graph moved them (map.follow_corrections)
  double seconds = 0;    // wall time of the run, from the first frame read to the last tracked
  double fps = 0;        // frames / seconds (end to end, decoding included)
  // m/s^2: the acceleration noise trajectory.txt's smoothing used (measured from the run unless
  // trajectory.measure_acceleration is false; TrajectorySmoother); 0 when nothing was smoothed
  double acceleration_noise = 0;
  int dropped = 0;       // frames a live stream dropped because the pipeline was still busy
  bool stopped = false;  // the run was ended early (Ctrl-C); its result covers the frames processed
  int body_fits_offered = 0;  // people-frames sent to the body thread (bodies.fit_every apart per person)
  int body_fits_skipped = 0;  // of those, dropped because the body thread was behind (interpolated)
  std::string detector;  // backend that ran ("none" when people were not removed)
  // The world's up (unit, against gravity) in the world frame (the first camera's), from the floor
  // and table tops of the first frames (UpDirectionEstimator); the first camera's -y when none
  // was seen (up_estimated false). The bodies were fitted upright to it.
  Eigen::Vector3d up_w = Eigen::Vector3d(0, -1, 0);
  bool up_estimated = false;
};

// One frame's result, as SlamSystem::process() returns it.
struct FrameResult {
  double timestamp = 0;
  TrackStatus status = TrackStatus::kLost;
  bool has_pose = false;                                  // tracked, bridged or relocalised
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity(); // as tracked now; the pose graph may
                                                          // still correct it (SlamResult has the final one)
  cv::Mat static_depth;  // D_b: CV_32F metres, the people removed (the input depth without a detector)
  cv::Mat removed;       // CV_8U, 255 = depth the filter removed; empty without a detector
  struct Person {
    int id = 0;           // the human tracker's id (stable across frames)
    Eigen::Vector3d p_c;  // centre in this camera's frame (paper eq. 2), metres
    Eigen::Vector3d p_w;  // ... in the world frame (eq. 3) with T_w_c; meaningful with has_pose
  };
  std::vector<Person> people;  // with a detector and options.track_humans
};

// A run's final result, as SlamSystem::finish() returns it; writeSlamResult() saves it.
struct SlamResult {
  SlamRunSummary summary;
  Trajectory trajectory;                // one pose per posed frame, loop-corrected, smoothed (T_w_c)
  bool has_humans = false;              // a detector ran and options.track_humans is set
  std::vector<HumanTrack> humans;       // each person's pelvis (or eq. 2 centre), trajectory's world frame
  std::vector<BodyTrack> bodies;        // each person's body per frame (with bodies.fit)
  std::shared_ptr<const BodyModel> body_model;  // the model the bodies are of (with bodies.fit)
  SceneOptions scene;                   // what writeSlamResult() puts into scene.ply / scene.obj
  std::vector<std::pair<double, TrackStatus>> frame_status;  // every frame's timestamp and status
  std::string tracker_stages_json;      // the tracker's sub-stage timings (StageStats::toJson)
  std::string body_stages_json = "{}";  // the body thread's timings per fit (BodyTrackFitter::stats)
  std::shared_ptr<Mapper> map;          // the fused map at the final poses; null without one
  Mapper::ExportOptions map_files;      // which map files writeSlamResult() writes
};

// The pipeline on frames one at a time. The caller owns the frame loop (a recorded sequence, a
// live camera); threads stay inside: the pose-graph back end and the mapper run in their own.
//
//   SlamSystem slam(options, createSlamDetector(options, folder, &name));
//   for (const Frame& frame : frames) slam.process(frame);
//   writeSlamResult(out_dir, slam.finish(), &slam.stats());
class SlamSystem {
 public:
  // detector: removes people from every frame; nullptr = none (the baseline). Throws pf2::Error
  // on options outside their ranges (validateOptions).
  SlamSystem(const SlamOptions& options, std::unique_ptr<HumanDetector> detector);
  // The detector chosen by options.detector when run() is called (it may need the sequence's
  // folder: the gt oracle reads its gt/ folder).
  explicit SlamSystem(const SlamOptions& options);
  ~SlamSystem();

  // One frame, in time order: people removed, camera tracked, people placed, the map fed. NOT
  // thread safe: one caller, as for finish().
  FrameResult process(const Frame& frame);
  // process() in two steps, so that detection can run ahead in a thread of its own (SlamRunner):
  // detect() gives a frame's people (none without a detector); it may be called from another
  // thread than process(), frames in order, ahead of process(). process(frame, detections) is the
  // rest with those detections. Each of the two from one thread at a time.
  Detections detect(const Frame& frame);
  FrameResult process(const Frame& frame, const Detections& detections);
  // Counts so far (frames, lost, ...), for a progress line. Front end's thread only.
  const SlamRunSummary& progress() const;
  size_t keyframeCount() const;
  const SlamOptions& options() const { return options_; }
  // True when the system has a detector (people are removed, masks exist).
  bool removesPeople() const;
  // Stops the threads after an error and forgets the frames processed: the system is as new.
  void abandon();
  // Waits for the back end and the map and returns the final result. Call once, after the last
  // process(); process() may not be called after it.
  SlamResult finish();
  // From now on each frame's removed mask is written as DIR/<timestamp>.png (DIR must exist).
  void writeMasksTo(const std::string& dir);

  // A recorded sequence, as pf2_slam runs it: the frames of `source` (decoded ahead in a loader
  // thread) through process(), then writeSlamResult() into out_dir (created if needed):
  //   trajectory.txt  TUM format, one line per frame that has a pose, loop-corrected (T_w_c),
  //                   positions smoothed (SlamOptions::trajectory)
  //   stats.json      frames, lost/bridged/relocalised counts, per-stage median/p90 ms,
  //                   end-to-end fps, each frame's tracking status
  //   map.ply, map.bt, map.ot (and map.pcd, map.obj on request) when the map is built
  //   humans.txt      `timestamp id x y z` person centres (eq. 2-3) in trajectory.txt's world
  //                   frame, when a detector ran and options.track_humans is set
  //   masks/          with options.write_masks
  // sequence_folder (may be empty) is where a gt/ folder is looked for. Throws pf2::Error naming
  // the file on bad input; outputs are written atomically. Call once, instead of process().
  SlamRunSummary run(const FrameSource& source, const std::string& sequence_folder,
                     const std::string& out_dir);

  // Available after finish() or run().
  const Trajectory& trajectory() const { return trajectory_; }
  // Per-stage timings (load, detect, filter, track, humans, frame, map, map_export). Thread safe.
  const StageStats& stats() const { return stats_; }
  StageStats& stats() { return stats_; }

 private:
  class Pipeline;
  Pipeline& pipeline();

  SlamOptions options_;
  StageStats stats_;
  std::unique_ptr<Pipeline> pipeline_;
  Trajectory trajectory_;
};

// The detector options.detector names: "none" gives nullptr, "auto" the learned detector when its
// models are installed (else HOG, with a warning on stderr), "gt" the oracle reading
// sequence_folder/gt. *chosen gets the name of what was made. Throws pf2::Error for an unknown or
// unavailable detector.
std::unique_ptr<HumanDetector> createSlamDetector(const SlamOptions& options, const std::string& sequence_folder,
                                                  std::string* chosen);

// Saves a result folder: trajectory.txt, humans.txt (with has_humans), the map files (with a map;
// their export time goes into `stages` as "map_export"), then stats.json (summary, `stages`, the
// tracker's sub-stages, each frame's status). The files appear as a set: written into a staging
// folder in out_dir and moved into place once all were written, stats.json last (a folder with
// stats.json holds one complete run); on failure out_dir keeps what it had. `extra_files`, when given, writes more files (the run report) into the staging folder it is
// passed, so they belong to the same set. Throws pf2::Error naming the file.
using ExtraFiles = std::function<void(const std::string& staging_dir, const SlamResult& result)>;
void writeSlamResult(const std::string& out_dir, const SlamResult& result, StageStats* stages,
                     const ExtraFiles& extra_files = nullptr);

}  // namespace pf2
