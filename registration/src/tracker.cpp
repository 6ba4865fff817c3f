#include "pf2/registration/tracker.h"

#include <chrono>
#include <climits>

#include "pf2/core/pose.h"

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

PoseGraphBackend::Options backendOptions(const Tracker::Options& options) {
  PoseGraphBackend::Options backend = options.backend;
  backend.verification = options.odometry;
  return backend;
}

}  // namespace

const char* toString(TrackStatus status) {
  switch (status) {
    case TrackStatus::kOk: return "tracked";
    case TrackStatus::kBridged: return "bridged";
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
      cleaner_(options.cleaning),
      backend_(std::make_unique<PoseGraphBackend>(backendOptions(options), &map_, &loops_)) {
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
  const double depth_fraction =
      double(current.valid_depth_pixels) / std::max(1, frame.depth.rows * frame.depth.cols);

  if (!initialised_) {
    if (depth_fraction < options_.min_keyframe_depth_fraction) return result;  // kLost: nothing to start from
    SubStageTimer timer(&stats_, &result, "keyframe");
    initialised_ = true;
    result.status = TrackStatus::kOk;
    createKeyframe(&current, &result);
    keepFrame(&current, true, frame.timestamp);
    return result;
  }

  // Too little static depth (a person filling the view) leaves the pose unconstrained: such a
  // frame is not measured (a synthetic frame with 3.5 % depth was tracked 42 cm off).
  const bool measurable = depth_fraction >= options_.min_tracking_depth_fraction;
  const Eigen::Isometry3d T_k_prior = options_.constant_velocity ? T_k_c_ * T_prev_cur_ : T_k_c_;
  bool measured = false;
  bool chained = false;  // measured against the previous frame: the keyframe no longer overlaps
  if (measurable && !lost_) {
    measured = alignToKeyframe(&current, T_k_prior, frame.timestamp, &result);
    if (!measured) measured = chained = alignToPreviousFrame(&current, T_k_prior, frame.timestamp, &result);
    if (measured) result.status = TrackStatus::kOk;
  }
  if (measurable && !measured) {
    SubStageTimer timer(&stats_, &result, "relocalise");
    measured = relocalise(&current, &result);
    if (measured) result.status = TrackStatus::kRelocalised;
  }
  if (!measured) {
    if (lost_ || bridged_in_row_ >= options_.max_bridged_frames) {
      lost_ = true;
      previous_ = OdometryFrame();
      result.status = TrackStatus::kLost;
      return result;
    }
    // Bridged: the prior's pose, with the motion faded for the next frame.
    T_k_c_ = T_k_prior;
    T_prev_cur_ = interpolate(Eigen::Isometry3d::Identity(), T_prev_cur_, options_.bridge_motion_decay);
    result.status = TrackStatus::kBridged;
  }
  lost_ = false;
  ++frames_since_keyframe_;
  result.keyframe_id = reference_id_;
  result.T_k_c = T_k_c_;
  result.T_w_c = map_.pose(reference_id_) * T_k_c_;
  // A keyframe anchors every later frame and loop: it is only made from a measured frame with
  // enough static depth (the inlier ratio also drops when a person covers the view; the old
  // keyframe is kept until the view clears).
  if (measured && depth_fraction >= options_.min_keyframe_depth_fraction &&
      result.odometry.dense.hessian_condition <= options_.max_keyframe_condition &&
      (chained || selector_.needsKeyframe(T_k_c_, result.odometry.dense.inlier_ratio, frames_since_keyframe_))) {
    SubStageTimer timer(&stats_, &result, "keyframe");
    createKeyframe(&current, &result);
    result.T_k_c = Eigen::Isometry3d::Identity();
    result.T_w_c = map_.pose(result.keyframe_id);
  }
  keepFrame(&current, measured, frame.timestamp);
  return result;
}

bool Tracker::alignToKeyframe(OdometryFrame* current, const Eigen::Isometry3d& T_k_prior,
                              double timestamp, TrackResult* result) {
  SubStageTimer timer(&stats_, result, "odometry");
  // The constant-velocity prior first; a wrong velocity (one bad frame pair) can start the
  // alignment out of its basin, so the last pose itself is the second start.
  for (const Eigen::Isometry3d& start : {T_k_prior, T_k_c_}) {
    result->odometry = odometry_.estimate(reference_, current, start);
    if (result->odometry.valid && consistent(result->odometry.dense) &&
        withinReach(result->odometry.T_ref_cur, T_k_prior, timestamp)) {
      T_prev_cur_ = T_k_c_.inverse() * result->odometry.T_ref_cur;
      T_k_c_ = result->odometry.T_ref_cur;
      cleaner_.update(&reference_, *current, T_k_c_);
      return true;
    }
    if (start.isApprox(T_k_c_, 1e-9)) break;
  }
  return false;
}

bool Tracker::alignToPreviousFrame(OdometryFrame* current, const Eigen::Isometry3d& T_k_prior,
                                   double timestamp, TrackResult* result) {
  if (previous_.levels.empty()) return false;
  SubStageTimer timer(&stats_, result, "previous_frame");
  odometry_.makeReference(&previous_);
  const Eigen::Isometry3d T_previous_prior = T_k_previous_.inverse() * T_k_prior;
  const OdometryResult attempt = odometry_.estimate(previous_, current, T_previous_prior);
  const Eigen::Isometry3d T_k_c = T_k_previous_ * attempt.T_ref_cur;
  if (!attempt.valid || !withinReach(T_k_c, T_k_prior, timestamp)) return false;
  result->odometry = attempt;
  T_prev_cur_ = T_k_c_.inverse() * T_k_c;
  T_k_c_ = T_k_c;
  return true;
}

bool Tracker::consistent(const DenseAlignment& alignment) const {
  return alignment.agreement() >= options_.min_tracking_agreement;
}

bool Tracker::withinReach(const Eigen::Isometry3d& T_k_c, const Eigen::Isometry3d& T_k_prior,
                          double timestamp) const {
  const double dt = std::max(0.0, timestamp - last_measured_timestamp_);
  const double tol_t = options_.guard_tolerance_translation, tol_r = options_.guard_tolerance_rotation;
  const Eigen::Isometry3d T_measured_c = T_k_measured_.inverse() * T_k_c;
  const Eigen::Isometry3d T_prior_c = T_k_prior.inverse() * T_k_c;
  return T_measured_c.translation().norm() <= tol_t + options_.max_speed * dt &&
         rotationAngle(T_measured_c.rotation()) <= tol_r + options_.max_angular_speed * dt &&
         T_prior_c.translation().norm() <= tol_t + 0.5 * options_.max_acceleration * dt * dt &&
         rotationAngle(T_prior_c.rotation()) <= tol_r + 0.5 * options_.max_angular_acceleration * dt * dt;
}

void Tracker::keepFrame(OdometryFrame* current, bool measured, double timestamp) {
  if (!measured) {
    // The last measured frame stays the frame-to-frame fallback while frames are bridged: it
    // still overlaps the view when the keyframe no longer does, and the divergence guard's
    // reach grows with the time since it.
    ++bridged_in_row_;
    return;
  }
  bridged_in_row_ = 0;
  last_measured_timestamp_ = timestamp;
  T_k_measured_ = T_k_c_;
  // A frame that became the keyframe was moved into reference_: the keyframe is its own fallback.
  previous_ = current->levels.empty() ? OdometryFrame() : std::move(*current);
  T_k_previous_ = T_k_c_;
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
  cleaner_.reset();
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
    if (!attempt.valid && id == reference_id_) {
      // Features fail on blurred or plain views; from the last pose the dense alignment may
      // still find the keyframe (a camera that stood still while a person passed close).
      attempt.dense = odometry_.refine(keyframe, *frame, T_k_c_);
      attempt.valid = attempt.dense.valid;
      attempt.T_ref_cur = attempt.dense.T_ref_cur;
    }
    // Relocalisation has no motion prior to confirm it: it needs more overlap than tracking, or,
    // where people left the views little overlap, the keyframe aligned back onto the frame
    // agreeing with it (the back end's local-edge rule).
    if (attempt.valid && attempt.dense.inlier_ratio < options_.min_relocalisation_inlier_ratio) {
      odometry_.makeReference(frame);
      attempt.valid = backend_->agreesBothWays(keyframe, *frame, attempt.dense).has_value();
    }
    if (!attempt.valid) {
      if (id == ids.front()) result->odometry = attempt;
      continue;
    }
    result->odometry = attempt;
    if (id != reference_id_) {
      reference_ = std::move(candidate);
      reference_id_ = id;
      cleaner_.reset();
    }
    T_k_c_ = attempt.T_ref_cur;
    T_prev_cur_ = Eigen::Isometry3d::Identity();  // the motion across the gap is unknown
    frames_since_keyframe_ = 0;
    return true;
  }
  return false;
}

}  // namespace pf2
