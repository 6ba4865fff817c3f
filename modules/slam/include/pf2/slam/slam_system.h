#pragma once
// The pipeline of DESIGN.md: frames -> person detector -> Dual-BBox filter -> tracker -> mapper,
// and the human tracker on the filter's people once the frame's pose is known.
//
// Threads: a loader decodes frames ahead; the calling thread runs detection, filtering and
// tracking (the front end), then associates the people's centres (microseconds); the tracker's
// pose-graph back end (loop closure) runs in its own thread; a mapper thread fuses keyframes into
// the TSDF/OctoMap and re-fuses them when the pose graph moves them. Only the front end touches the
// detector, filter, tracker and human tracker; only the mapper thread touches the Mapper.
#include <memory>
#include <string>

#include "pf2/core/frame_source.h"
#include "pf2/core/pose.h"
#include "pf2/core/stage_timer.h"
#include "pf2/slam/slam_options.h"

namespace pf2 {

struct SlamRunSummary {
  int frames = 0;        // frames processed
  int tracked = 0;       // frames with a pose (tracked, bridged or relocalised)
  int lost = 0;          // frames without a pose
  int relocalised = 0;   // frames where tracking came back
  int bridged = 0;       // frames given the motion prior's pose (no alignment held)
  int keyframes = 0;
  int loop_closures = 0; // verified loop edges in the keyframe pose graph
  int local_edges = 0;   // verified edges between near keyframes (the back end's local window)
  double seconds = 0;    // wall time of the run, from the first frame read to the last tracked
  double fps = 0;        // frames / seconds (end to end, decoding included)
  std::string detector;  // backend that ran ("none" when people were not removed)
};

class SlamSystem {
 public:
  explicit SlamSystem(const SlamOptions& options);
  ~SlamSystem();

  // Runs over the frames of `source` and writes into out_dir (created if needed):
  //   trajectory.txt  TUM format, one line per frame that has a pose, loop-corrected (T_w_c)
  //   stats.json      frames, lost/bridged/relocalised counts, per-stage median/p90 ms,
  //                   end-to-end fps, each frame's tracking status
  //   map.ply, map.bt, map.ot (and map.pcd on request) when the map is built
  //   humans.txt      `timestamp id x y z` person centres (eq. 2-3) in trajectory.txt's world
  //                   frame, when a detector ran and options.track_humans is set
  // sequence_folder (may be empty) is where a gt/ folder is looked for. Throws pf2::Error naming
  // the file on bad input; outputs are written atomically. NOT thread safe; call once.
  SlamRunSummary run(const FrameSource& source, const std::string& sequence_folder,
                     const std::string& out_dir);

  // Available after run().
  const Trajectory& trajectory() const { return trajectory_; }
  const StageStats& stats() const { return stats_; }

 private:
  SlamOptions options_;
  Trajectory trajectory_;
  StageStats stats_;
};

}  // namespace pf2
