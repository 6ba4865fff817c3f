#pragma once
// The tracking back-end: keeps the keyframe pose graph, looks for loops among keyframes by
// appearance (LoopDetector), verifies each candidate geometrically (ORB RANSAC + dense
// refinement), and when a loop is accepted optimises the graph and writes the corrected poses
// into the KeyframeMap (and hands them to a callback, e.g. for the mapper to re-integrate).
//
// Threading: addKeyframe() only queues and returns at once; the work happens in processPending(),
// either in the caller's thread or in the back-end's own worker thread (start()/stop()). All
// public methods are thread safe. The callback runs in whichever thread processes the queue and
// must not call back into the back-end.
#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include <Eigen/Geometry>

#include "pf2/registration/keyframe.h"
#include "pf2/registration/loop_detector.h"
#include "pf2/registration/pose_graph.h"
#include "pf2/registration/rgbd_odometry.h"

namespace pf2 {

class PoseGraphBackend {
 public:
  struct Options {
    PoseGraph::Options graph;
    RgbdOdometry::Options verification;  // odometry used to verify loop candidates
    double odometry_translation_sigma = 0.01;  // metres, per keyframe-to-keyframe edge
    double odometry_rotation_sigma = 0.01;     // radians, per keyframe-to-keyframe edge
    double loop_translation_sigma = 0.01;      // metres, verified loop edge
    double loop_rotation_sigma = 0.01;         // radians, verified loop edge
    // A loop is only accepted when the dense verification's inlier ratio reaches this (tracking
    // accepts less: a wrong loop costs more than a lost frame).
    double min_loop_inlier_ratio = 0.7;
    // The candidate is also aligned onto the new keyframe (from the inverse of the first
    // result) with at least this inlier ratio (lower: overlap is asymmetric between views far
    // apart; right loops on the synthetic loop gave 0.5-0.6) ...
    double min_loop_reverse_inlier_ratio = 0.4;
    // ... and the two results may differ by at most this much.
    double max_loop_asymmetry_translation = 0.01;  // metres
    double max_loop_asymmetry_rotation = 0.01;     // radians
    int min_loop_gap = 10;       // a loop joins keyframes at least this many ids apart
    int max_candidates = 3;      // candidates verified per new keyframe, best-voted first
    // Local window: each new keyframe is also aligned (dense, from the graph's relative pose) onto
    // up to this many of the keyframes closer than min_loop_gap ids, other than its reference,
    // within local_radius and local_max_angle of it, nearest first. Verified like a loop, these edges tie together the
    // keyframes of one place, so the chain's drift is corrected as it arises (the neighbouring
    // keyframe constraints of DVO-SLAM) instead of only when a loop closes. 0 = chain and loops.
    int local_edges = 3;
    double local_radius = 0.5;  // metres between the keyframes' positions
    double local_max_angle = 0.5;  // radians between their orientations (views ~30 degrees apart
                                   // still share most of a 60-degree field of view)
    double min_local_agreement = 0.7;  // a local alignment's inliers per associated point
  };

  struct LoopClosure {
    int from = -1;  // the older keyframe
    int to = -1;    // the newer keyframe
    Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();
    double inlier_ratio = 0.0;  // dense verification's inlier ratio
  };

  using CorrectionCallback = std::function<void(const std::map<int, Eigen::Isometry3d>& T_w_k)>;

  // map and loops must outlive the back-end; the tracker adds keyframes and descriptors to them.
  PoseGraphBackend(const Options& options, KeyframeMap* map, LoopDetector* loops);
  ~PoseGraphBackend();  // stops the worker (finishing the queue)
  PoseGraphBackend(const PoseGraphBackend&) = delete;
  PoseGraphBackend& operator=(const PoseGraphBackend&) = delete;

  // Called after every optimisation with all corrected keyframe poses. Set it before start().
  void setCorrectionCallback(CorrectionCallback callback);

  // Queues keyframe `id` (already in the map and the loop detector), measured from keyframe
  // reference_id as T_ref_k; reference_id = -1 for the first keyframe.
  void addKeyframe(int id, int reference_id, const Eigen::Isometry3d& T_ref_k);
  // Processes everything queued, in this thread.
  void processPending();
  // Worker thread that processes the queue as keyframes arrive; stop() finishes the queue first.
  void start();
  void stop();
  // Blocks until the queue is empty and its last keyframe processed.
  void waitIdle();

  // The local-edge rule, for any caller: T_ref_cur of `forward` (current aligned onto reference)
  // when it is consistent and the reference aligned back onto `current` agrees with it
  // (consistency, not overlap: views that people cut up overlap little). Both frames must have
  // been made references. Thread safe.
  std::optional<Eigen::Isometry3d> agreesBothWays(const OdometryFrame& reference, const OdometryFrame& current,
                                                  const DenseAlignment& forward) const {
    return verified(reference, current, forward, true);
  }

  std::vector<LoopClosure> loopClosures() const;
  int optimisations() const;
  int localEdges() const;  // verified local-window edges added so far

 private:
  struct Pending {
    int id;
    int reference_id;
    Eigen::Isometry3d T_ref_k;
  };
  void process(const Pending& pending);
  void addNode(const Pending& pending);
  // Keyframes of the local window of `id`, nearest first (Options::local_edges).
  std::vector<int> localNeighbours(int id, int reference_id) const;
  // Whether an alignment may become an edge. A loop needs overlap (inlier_ratio, inliers per
  // sample of the newer view, at least min_inlier_ratio); keyframes of a local window, whose
  // people hid different parts of the scene, may overlap little and need consistency instead
  // (Options::min_local_agreement) and the odometry's min_inliers.
  bool acceptable(const DenseAlignment& a, double min_inlier_ratio, bool local) const;
  // T_old_new of an older keyframe and the new one when the dense alignment `forward` is
  // acceptable and holds in the other direction too; nullopt otherwise.
  std::optional<Eigen::Isometry3d> verified(const OdometryFrame& old, const OdometryFrame& current,
                                            const DenseAlignment& forward, bool local) const;
  void optimiseAndPublish();
  void workerLoop();

  Options options_;
  KeyframeMap* map_;
  LoopDetector* loops_;
  RgbdOdometry verifier_;
  CorrectionCallback callback_;

  std::mutex work_mutex_;  // serialises processing (graph_ is only touched under it)
  PoseGraph graph_;

  mutable std::mutex queue_mutex_;
  std::condition_variable queue_changed_;
  std::deque<Pending> queue_;
  bool busy_ = false;
  bool stopping_ = false;
  std::exception_ptr error_;  // what ended the worker thread, rethrown by waitIdle()
  std::thread worker_;
  std::vector<LoopClosure> closures_;
  int optimisations_ = 0;
  int local_edges_ = 0;
};

}  // namespace pf2
