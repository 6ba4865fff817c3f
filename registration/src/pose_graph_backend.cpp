#include "pf2/registration/pose_graph_backend.h"

#include <algorithm>

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
  queue_changed_.wait(lock, [this] { return (queue_.empty() && !busy_) || error_; });
  if (error_) std::rethrow_exception(error_);
}

void PoseGraphBackend::workerLoop() {
  try {
    for (;;) {
      {
        std::unique_lock<std::mutex> lock(queue_mutex_);
        queue_changed_.wait(lock, [this] { return !queue_.empty() || stopping_; });
        if (queue_.empty() && stopping_) return;
      }
      processPending();
    }
  } catch (...) {
    // Handed to the front end by waitIdle(); the queue is dropped so that no one waits for it.
    std::lock_guard<std::mutex> lock(queue_mutex_);
    error_ = std::current_exception();
    queue_.clear();
    busy_ = false;
    queue_changed_.notify_all();
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

int PoseGraphBackend::localEdges() const {
  std::lock_guard<std::mutex> lock(queue_mutex_);
  return local_edges_;
}

void PoseGraphBackend::process(const Pending& pending) {
  std::lock_guard<std::mutex> work(work_mutex_);
  addNode(pending);
  const std::shared_ptr<const Keyframe> keyframe = map_->keyframe(pending.id);
  const std::vector<int> neighbours = localNeighbours(pending.id, pending.reference_id);
  const std::vector<LoopDetector::Candidate> candidates = loops_->query(
      keyframe->descriptors, pending.id - options_.min_loop_gap, options_.max_candidates);
  if (neighbours.empty() && candidates.empty()) return;

  OdometryFrame current = verifier_.prepare(*keyframe);
  bool added = false;
  for (const int id : neighbours) {
    const OdometryFrame old = verifier_.prepare(*map_->keyframe(id));
    const Eigen::Isometry3d guess = graph_.pose(id).inverse() * graph_.pose(pending.id);
    const std::optional<Eigen::Isometry3d> T_old_new =
        verified(old, current, verifier_.refine(old, current, guess), true);
    if (!T_old_new) continue;
    // Rejectable like a loop edge: a wrong local alignment must not bend the chain.
    graph_.addEdge(makeEdge(id, pending.id, *T_old_new, options_.loop_translation_sigma,
                            options_.loop_rotation_sigma, true));
    added = true;
    std::lock_guard<std::mutex> lock(queue_mutex_);
    ++local_edges_;
  }
  for (const LoopDetector::Candidate& candidate : candidates) {
    if (!graph_.hasNode(candidate.keyframe_id)) continue;
    const OdometryFrame old = verifier_.prepare(*map_->keyframe(candidate.keyframe_id));
    const OdometryResult check = verifier_.estimateWithoutPrior(old, &current);
    if (!check.valid) continue;
    const std::optional<Eigen::Isometry3d> T_old_new = verified(old, current, check.dense, false);
    if (!T_old_new) continue;
    const PoseGraph::Edge edge = makeEdge(candidate.keyframe_id, pending.id, *T_old_new,
                                          options_.loop_translation_sigma, options_.loop_rotation_sigma, true);
    graph_.addEdge(edge);
    added = true;
    std::lock_guard<std::mutex> lock(queue_mutex_);
    closures_.push_back({edge.from, edge.to, edge.T_from_to, check.dense.inlier_ratio});
  }
  if (added) optimiseAndPublish();
}

// The node starts where its reference is now in the graph (it may have moved since tracking
// measured the keyframe), so a correction in flight is not undone.
void PoseGraphBackend::addNode(const Pending& pending) {
  if (pending.reference_id >= 0 && pending.reference_id != pending.id &&
      graph_.hasNode(pending.reference_id)) {
    graph_.addNode(pending.id, graph_.pose(pending.reference_id) * pending.T_ref_k);
    graph_.addEdge(makeEdge(pending.reference_id, pending.id, pending.T_ref_k,
                            options_.odometry_translation_sigma, options_.odometry_rotation_sigma,
                            false));
  } else {
    graph_.addNode(pending.id, map_->pose(pending.id));
  }
}

std::vector<int> PoseGraphBackend::localNeighbours(int id, int reference_id) const {
  std::vector<std::pair<double, int>> near;
  if (options_.local_edges <= 0) return {};
  const Eigen::Isometry3d pose = graph_.pose(id);
  for (int other = std::max(0, id - options_.min_loop_gap + 1); other < id; ++other) {
    if (other == reference_id || !graph_.hasNode(other)) continue;
    const Eigen::Isometry3d relative = graph_.pose(other).inverse() * pose;
    const double distance = relative.translation().norm();
    const double angle = rotationAngle(relative.rotation());
    // Nearest first, a metre counted like a radian (as the keyframe thresholds are alike).
    if (distance <= options_.local_radius && angle <= options_.local_max_angle)
      near.emplace_back(distance + angle, other);
  }
  std::sort(near.begin(), near.end());
  std::vector<int> ids;
  for (size_t k = 0; k < near.size() && static_cast<int>(k) < options_.local_edges; ++k)
    ids.push_back(near[k].second);
  return ids;
}

bool PoseGraphBackend::acceptable(const DenseAlignment& a, double min_inlier_ratio, bool local) const {
  if (!local) return a.valid && a.inlier_ratio >= min_inlier_ratio;
  const RgbdOdometry::Options& o = verifier_.options();
  return a.T_ref_cur.matrix().allFinite() && a.inlier_points >= o.min_inliers &&
         a.hessian_condition <= o.max_condition &&
         a.agreement() >= options_.min_local_agreement;
}

std::optional<Eigen::Isometry3d> PoseGraphBackend::verified(const OdometryFrame& old,
                                                           const OdometryFrame& current,
                                                           const DenseAlignment& forward,
                                                           bool local) const {
  if (!acceptable(forward, options_.min_loop_inlier_ratio, local)) return std::nullopt;
  // The inlier ratio counts only the new keyframe's samples: a keyframe with a small patch of
  // scene can align wrongly yet fully. The old keyframe is aligned onto the new one as well
  // (overlap on both sides; views 0.6 m apart overlap asymmetrically, hence a lower ratio), and
  // both directions must agree.
  const DenseAlignment back = verifier_.refine(current, old, forward.T_ref_cur.inverse());
  if (!acceptable(back, options_.min_loop_reverse_inlier_ratio, local)) return std::nullopt;
  const Eigen::Isometry3d asymmetry = back.T_ref_cur * forward.T_ref_cur;
  if (asymmetry.translation().norm() > options_.max_loop_asymmetry_translation ||
      rotationAngle(asymmetry.rotation()) > options_.max_loop_asymmetry_rotation)
    return std::nullopt;
  return forward.T_ref_cur;
}

void PoseGraphBackend::optimiseAndPublish() {
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
