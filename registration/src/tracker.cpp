#include "pf2/registration/tracker.h"

#include <chrono>
#include <climits>

namespace pf2 {
namespace {

// Times one sub-stage into both the frame's result and the tracker's statistics.
class SubStageTimer {
 public:
  SubStageTimer(StageStats* stats, TrackResult* result, const char* name)
      : stats_(stats), result_(result), name_(name), start_(std::chrono::steady_clock::now()) {}
  ~SubStageTimer() {
    const double ms = std::chrono::duration<double, std::milli>(
                          std::chrono::steady_clock::now() - start_).count();
    stats_->add(name_, ms);
    result_->stage_ms.emplace_back(name_, ms);
  }
  SubStageTimer(const SubStageTimer&) = delete;
  SubStageTimer& operator=(const SubStageTimer&) = delete;

 private:
  StageStats* stats_;
  TrackResult* result_;
  const char* name_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

const char* toString(TrackStatus status) {
  switch (status) {
    case TrackStatus::kOk: return "ok";
    case TrackStatus::kLost: return "lost";
    case TrackStatus::kRelocalised: return "relocalised";
  }
  return "unknown";
}

Tracker::Tracker(const Options& options)
    : options_(options),
      odometry_(options.odometry),
      selector_(options.keyframes),
      loops_(options.loops),
      backend_(std::make_unique<PoseGraphBackend>(options.backend, &map_, &loops_)) {
  if (options_.asynchronous_backend) backend_->start();
}

Tracker::~Tracker() { backend_->stop(); }

void Tracker::finish() { backend_->waitIdle(); }

TrackResult Tracker::track(const Frame& frame, const cv::Mat& person_mask) {
  TrackResult result;
  OdometryFrame current;
  {
    SubStageTimer timer(&stats_, &result, "prepare");
    current = odometry_.prepare(frame, person_mask);
  }

  if (!initialised_) {
    const double fraction =
        double(current.valid_depth_pixels) / std::max(1, frame.depth.rows * frame.depth.cols);
    if (fraction < options_.min_keyframe_depth_fraction) return result;  // kLost: nothing to start from
    SubStageTimer timer(&stats_, &result, "keyframe");
    initialised_ = true;
    result.status = TrackStatus::kOk;
    createKeyframe(&current, &result);
    return result;
  }

  // Too little static depth (a person filling the view) leaves the pose unconstrained: such a
  // frame gets no pose rather than a guess that may be tens of centimetres off.
  const double depth_fraction =
      double(current.valid_depth_pixels) / std::max(1, frame.depth.rows * frame.depth.cols);
  if (depth_fraction < options_.min_tracking_depth_fraction) {
    lost_ = true;
    return result;  // kLost
  }
  bool tracked = false;
  if (!lost_) {
    SubStageTimer timer(&stats_, &result, "odometry");
    const Eigen::Isometry3d guess =
        options_.constant_velocity ? T_k_c_ * T_prev_cur_ : T_k_c_;
    result.odometry = odometry_.estimate(reference_, &current, guess);
    if (result.odometry.valid) {
      T_prev_cur_ = T_k_c_.inverse() * result.odometry.T_ref_cur;
      T_k_c_ = result.odometry.T_ref_cur;
      result.status = TrackStatus::kOk;
      tracked = true;
    }
  }
  if (!tracked) {
    SubStageTimer timer(&stats_, &result, "relocalise");
    if (relocalise(&current, &result)) {
      result.status = TrackStatus::kRelocalised;
      tracked = true;
    }
  }
  if (!tracked) {
    lost_ = true;
    result.status = TrackStatus::kLost;
    return result;
  }
  lost_ = false;
  ++frames_since_keyframe_;
  result.keyframe_id = reference_id_;
  result.T_k_c = T_k_c_;
  result.T_w_c = map_.pose(reference_id_) * T_k_c_;
  // A keyframe anchors every later frame and loop: it is only made from a frame with enough
  // static depth (the inlier ratio also drops when a person covers the view; the old keyframe
  // is kept until the view clears).
  if (depth_fraction >= options_.min_keyframe_depth_fraction &&
      selector_.needsKeyframe(T_k_c_, result.odometry.dense.inlier_ratio, frames_since_keyframe_)) {
    SubStageTimer timer(&stats_, &result, "keyframe");
    createKeyframe(&current, &result);
    result.T_k_c = Eigen::Isometry3d::Identity();
    result.T_w_c = map_.pose(result.keyframe_id);
  }
  return result;
}

void Tracker::createKeyframe(OdometryFrame* frame, TrackResult* result) {
  odometry_.makeReference(frame);
  // Placed relative to its reference under the map's lock, so a pose-graph correction that lands
  // between tracking and this call moves the new keyframe along with its reference.
  const int id = reference_id_ >= 0 ? map_.addRelative(makeKeyframe(*frame), reference_id_, T_k_c_)
                                    : map_.add(makeKeyframe(*frame), Eigen::Isometry3d::Identity());
  loops_.add(id, frame->descriptors);
  backend_->addKeyframe(id, reference_id_, reference_id_ >= 0 ? T_k_c_ : Eigen::Isometry3d::Identity());
  reference_ = std::move(*frame);
  reference_id_ = id;
  T_k_c_ = Eigen::Isometry3d::Identity();
  frames_since_keyframe_ = 0;
  result->keyframe_id = id;
  result->keyframe_created = true;
  if (!options_.asynchronous_backend) {
    SubStageTimer timer(&stats_, result, "backend");
    backend_->processPending();
  }
}

bool Tracker::relocalise(OdometryFrame* frame, TrackResult* result) {
  odometry_.featureAligner().extract(frame);
  std::vector<int> ids{reference_id_};
  for (const LoopDetector::Candidate& c :
       loops_.query(frame->descriptors, INT_MAX, options_.relocalisation_candidates))
    if (c.keyframe_id != reference_id_) ids.push_back(c.keyframe_id);

  for (int id : ids) {
    OdometryFrame candidate;
    if (id != reference_id_) candidate = odometry_.prepare(*map_.keyframe(id));
    const OdometryFrame& keyframe = id == reference_id_ ? reference_ : candidate;
    OdometryResult attempt = odometry_.estimateWithoutPrior(keyframe, frame);
    // Relocalisation has no motion prior to confirm it: it needs more overlap than tracking.
    if (attempt.dense.inlier_ratio < options_.min_relocalisation_inlier_ratio) attempt.valid = false;
    if (!attempt.valid) {
      if (id == ids.front()) result->odometry = attempt;
      continue;
    }
    result->odometry = attempt;
    if (id != reference_id_) {
      reference_ = std::move(candidate);
      reference_id_ = id;
    }
    T_k_c_ = attempt.T_ref_cur;
    T_prev_cur_ = Eigen::Isometry3d::Identity();  // the motion across the gap is unknown
    frames_since_keyframe_ = 0;
    return true;
  }
  return false;
}

}  // namespace pf2
