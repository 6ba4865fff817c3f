#include "pf2/registration/pose_graph_backend.h"

#include "pf2/core/error.h"
#include "pf2/core/pose.h"

namespace pf2 {
namespace {

PoseGraph::Edge makeEdge(int from, int to, const Eigen::Isometry3d& T_from_to,
                         double translation_sigma, double rotation_sigma, bool loop) {
  PoseGraph::Edge edge;
  edge.from = from;
  edge.to = to;
  edge.T_from_to = T_from_to;
  edge.translation_sigma = translation_sigma;
  edge.rotation_sigma = rotation_sigma;
  edge.loop = loop;
  return edge;
}

}  // namespace

PoseGraphBackend::PoseGraphBackend(const Options& options, KeyframeMap* map, LoopDetector* loops)
    : options_(options), map_(map), loops_(loops), verifier_(options.verification),
      graph_(options.graph) {
  if (!map_ || !loops_) throw Error("PoseGraphBackend: map and loop detector are required");
}

PoseGraphBackend::~PoseGraphBackend() { stop(); }

void PoseGraphBackend::setCorrectionCallback(CorrectionCallback callback) {
  std::lock_guard<std::mutex> lock(work_mutex_);
  callback_ = std::move(callback);
}

void PoseGraphBackend::addKeyframe(int id, int reference_id, const Eigen::Isometry3d& T_ref_k) {
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    queue_.push_back({id, reference_id, T_ref_k});
  }
  queue_changed_.notify_all();
}

void PoseGraphBackend::processPending() {
  for (;;) {
    Pending next;
    {
      std::lock_guard<std::mutex> lock(queue_mutex_);
      if (queue_.empty()) return;
      next = queue_.front();
      queue_.pop_front();
      busy_ = true;
    }
    process(next);
    {
      std::lock_guard<std::mutex> lock(queue_mutex_);
      busy_ = false;
    }
    queue_changed_.notify_all();
  }
}

void PoseGraphBackend::start() {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  if (worker_.joinable()) return;
  stopping_ = false;
  worker_ = std::thread([this] { workerLoop(); });
}

void PoseGraphBackend::stop() {
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    if (!worker_.joinable()) return;
    stopping_ = true;
  }
  queue_changed_.notify_all();
  worker_.join();
}

void PoseGraphBackend::waitIdle() {
  bool threaded;
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    threaded = worker_.joinable();
  }
  if (!threaded) {
    processPending();
    return;
  }
  std::unique_lock<std::mutex> lock(queue_mutex_);
  queue_changed_.wait(lock, [this] { return queue_.empty() && !busy_; });
}

void PoseGraphBackend::workerLoop() {
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(queue_mutex_);
      queue_changed_.wait(lock, [this] { return !queue_.empty() || stopping_; });
      if (queue_.empty() && stopping_) return;
    }
    processPending();
  }
}

std::vector<PoseGraphBackend::LoopClosure> PoseGraphBackend::loopClosures() const {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  return closures_;
}

int PoseGraphBackend::optimisations() const {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  return optimisations_;
}

void PoseGraphBackend::process(const Pending& pending) {
  std::lock_guard<std::mutex> work(work_mutex_);
  // The node starts where its reference is now in the graph (it may have moved since tracking
  // measured the keyframe), so a correction in flight is not undone.
  if (pending.reference_id >= 0 && pending.reference_id != pending.id &&
      graph_.hasNode(pending.reference_id)) {
    graph_.addNode(pending.id, graph_.pose(pending.reference_id) * pending.T_ref_k);
    graph_.addEdge(makeEdge(pending.reference_id, pending.id, pending.T_ref_k,
                            options_.odometry_translation_sigma, options_.odometry_rotation_sigma,
                            false));
  } else {
    graph_.addNode(pending.id, map_->pose(pending.id));
  }

  const std::shared_ptr<const Keyframe> keyframe = map_->keyframe(pending.id);
  const std::vector<LoopDetector::Candidate> candidates = loops_->query(
      keyframe->descriptors, pending.id - options_.min_loop_gap, options_.max_candidates);
  bool closed = false;
  if (!candidates.empty()) {
    OdometryFrame current = verifier_.prepare(*keyframe);
    for (const LoopDetector::Candidate& candidate : candidates) {
      if (!graph_.hasNode(candidate.keyframe_id)) continue;
      const OdometryFrame old = verifier_.prepare(*map_->keyframe(candidate.keyframe_id));
      const OdometryResult check = verifier_.estimateWithoutPrior(old, &current);
      if (!check.valid || check.dense.inlier_ratio < options_.min_loop_inlier_ratio) continue;
      // The inlier ratio counts only the new keyframe's samples: a keyframe with a small patch of
      // scene can align wrongly yet fully. The old keyframe is aligned onto the new one as well
      // (overlap on both sides; views 0.6 m apart overlap asymmetrically, hence a lower ratio),
      // and both directions must agree.
      const DenseAlignment back = verifier_.refine(current, old, check.T_ref_cur.inverse());
      if (!back.valid || back.inlier_ratio < options_.min_loop_reverse_inlier_ratio) continue;
      const Eigen::Isometry3d asymmetry = back.T_ref_cur * check.T_ref_cur;
      if (asymmetry.translation().norm() > options_.max_loop_asymmetry_translation ||
          rotationAngle(asymmetry.rotation()) > options_.max_loop_asymmetry_rotation)
        continue;
      const PoseGraph::Edge edge =
          makeEdge(candidate.keyframe_id, pending.id, check.T_ref_cur,
                   options_.loop_translation_sigma, options_.loop_rotation_sigma, true);
      graph_.addEdge(edge);
      closed = true;
      std::lock_guard<std::mutex> lock(queue_mutex_);
      closures_.push_back({edge.from, edge.to, edge.T_from_to, check.dense.inlier_ratio});
    }
  }
  if (!closed) return;
  graph_.optimize();
  const std::map<int, Eigen::Isometry3d> corrected = graph_.poses();
  map_->updatePoses(corrected);
  {
    std::lock_guard<std::mutex> lock(queue_mutex_);
    ++optimisations_;
  }
  if (callback_) callback_(corrected);
}

}  // namespace pf2
