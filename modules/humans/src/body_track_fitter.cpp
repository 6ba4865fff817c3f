#include "pf2/humans/body_track_fitter.h"

#include <algorithm>
#include <cmath>

#include "pf2/core/error.h"
#include "pf2/core/median.h"

namespace pf2 {

namespace {

// COCO-17 pairs joined by a bone below the head: shoulders, torso sides, hips, arms, legs.
constexpr int kBodySegments[][2] = {{5, 6},  {5, 11},  {6, 12},  {11, 12}, {5, 7},   {7, 9},
                                    {6, 8},  {8, 10},  {11, 13}, {13, 15}, {12, 14}, {14, 16}};

// Median of the points' depths; 0 without points.
double medianDepth(const std::vector<Eigen::Vector3d>& points_c) {
  if (points_c.empty()) return 0.0;
  std::vector<double> depths(points_c.size());
  for (size_t i = 0; i < points_c.size(); ++i) depths[i] = points_c[i].z();
  return upperMedian(&depths);
}

BodyFitter::Options withTemporal(BodyFitter::Options options, double weight_temporal, bool fit_shape) {
  options.weight_temporal = weight_temporal;
  options.fit_shape = fit_shape;
  return options;
}

// Metres between two keypoints on the plane `depth` metres in front of camera K.
double metresApart(const BodyKeypoint& a, const BodyKeypoint& b, double depth, const CameraIntrinsics& K) {
  return std::hypot((a.u - b.u) * depth / K.fx, (a.v - b.v) * depth / K.fy);
}

}  // namespace

double longestBodySegment(const std::array<BodyKeypoint, kCocoKeypointCount>& keypoints, double depth,
                          const CameraIntrinsics& K, double min_confidence) {
  double longest = 0.0;
  for (const auto& segment : kBodySegments) {
    const BodyKeypoint& a = keypoints[static_cast<size_t>(segment[0])];
    const BodyKeypoint& b = keypoints[static_cast<size_t>(segment[1])];
    if (!(a.confidence >= min_confidence && b.confidence >= min_confidence)) continue;
    longest = std::max(longest, metresApart(a, b, depth, K));
  }
  return longest;
}

double shortestTorsoSide(const std::array<BodyKeypoint, kCocoKeypointCount>& keypoints, double depth,
                         const CameraIntrinsics& K, double min_confidence, double edge_band) {
  const auto inView = [&](const BodyKeypoint& k) {
    return k.confidence >= min_confidence && k.u > edge_band && k.v > edge_band && k.u < K.width - 1 - edge_band &&
           k.v < K.height - 1 - edge_band;
  };
  double shortest = 0.0;
  for (const auto& [shoulder, hip] : {std::pair<int, int>{5, 11}, std::pair<int, int>{6, 12}}) {
    const BodyKeypoint& a = keypoints[static_cast<size_t>(shoulder)];
    const BodyKeypoint& b = keypoints[static_cast<size_t>(hip)];
    if (!(inView(a) && inView(b))) continue;
    const double side = metresApart(a, b, depth, K);
    shortest = shortest > 0.0 ? std::min(shortest, side) : side;
  }
  return shortest;
}

// What the fitting thread remembers of one track.
struct BodyTrackFitter::TrackState {
  bool has_previous = false;
  BodyParameters previous_c;  // the last fit, in its camera frame
  Eigen::Isometry3d T_w_c_previous = Eigen::Isometry3d::Identity();
  double previous_time = 0;
  int shape_fits = 0;         // fits that contributed to the shape
  Eigen::VectorXd shape_sum = Eigen::VectorXd::Zero(BodyFitter::Options::kShapeCount);
  bool shapeHeld(int needed) const { return shape_fits >= needed; }
  Eigen::VectorXd shape() const { return shape_sum / std::max(1, shape_fits); }
};

BodyTrackFitter::BodyTrackFitter(const BodyModel& model, const Options& options)
    : model_(model),
      options_(options),
      fitter_(model, withTemporal(options.fitter, options.weight_temporal, options.fitter.fit_shape)),
      fixed_shape_fitter_(model, withTemporal(options.fitter, options.weight_temporal, false)),
      queue_(static_cast<size_t>(std::max(1, options.queue_capacity))) {
  if (options_.asynchronous) thread_ = std::thread([this] { run(); });
}

BodyTrackFitter::~BodyTrackFitter() {
  queue_.close();
  if (thread_.joinable()) thread_.join();
}

bool BodyTrackFitter::wants(int track_id, int frame_index) const {
  const auto last = last_offered_.find(track_id);
  return last == last_offered_.end() || frame_index - last->second >= options_.fit_every;
}

bool BodyTrackFitter::offer(BodyObservation observation) {
  if (finished_) throw Error("BodyTrackFitter::offer: called after finish()");
  ++offered_;
  last_offered_[observation.track_id] = observation.frame_index;
  if (!options_.asynchronous) {
    fitOne(observation);
    return true;
  }
  if (queue_.tryPush(std::move(observation))) return true;
  ++dropped_;
  return false;
}

std::vector<BodyTrackFit> BodyTrackFitter::finish() {
  finished_ = true;
  queue_.close();
  if (thread_.joinable()) thread_.join();
  if (error_) std::rethrow_exception(error_);
  std::stable_sort(fits_.begin(), fits_.end(), [](const BodyTrackFit& a, const BodyTrackFit& b) {
    return a.track_id != b.track_id ? a.track_id < b.track_id : a.frame_index < b.frame_index;
  });
  return fits_;
}

void BodyTrackFitter::run() {
  try {
    while (std::optional<BodyObservation> observation = queue_.pop()) fitOne(*observation);
  } catch (...) {
    error_ = std::current_exception();
    while (queue_.pop()) {
    }
  }
}

// The fitter's input: keypoints, the person's depth points, the up direction, and the warm start
// (the previous fit moved into this camera frame) in *start when there is one.
BodyFitInput BodyTrackFitter::fitInput(const BodyObservation& o, const TrackState& track, BodyParameters* start) {
  BodyFitInput input;
  input.keypoints = o.keypoints;
  if (options_.refine_keypoints && !o.colour.empty()) {
    // The refiner works in the pixels of the colour it is given; the fit in the frame's.
    const cv::Rect2f box(o.box.x - o.colour_origin.x, o.box.y - o.colour_origin.y, o.box.width, o.box.height);
    std::array<BodyKeypoint, kCocoKeypointCount> refined = o.keypoints;
    for (BodyKeypoint& k : refined) k.u -= o.colour_origin.x, k.v -= o.colour_origin.y;
    ScopedStageTimer timer(&stats_, "refine");
    if (options_.refine_keypoints(o.colour, box, &refined)) {
      for (int k = 0; k < kCocoKeypointCount; ++k) {
        input.keypoints[k] = {refined[k].u + o.colour_origin.x, refined[k].v + o.colour_origin.y, refined[k].confidence};
      }
    }
  }
  if (!o.depth.empty()) {
    cv::Mat frame_depth(o.intrinsics.height, o.intrinsics.width, CV_32F, cv::Scalar(0));
    o.depth.copyTo(frame_depth(o.depth_area));
    input.points_c = depthPointsFromImage(frame_depth, o.intrinsics);
  }
  input.up_c = o.T_w_c.linear().transpose() * o.up_w;
  if (track.has_previous && o.timestamp - track.previous_time <= options_.warm_start_gap) {
    const Eigen::Isometry3d T_now_previous = o.T_w_c.inverse() * track.T_w_c_previous;
    const Eigen::Vector3d rest_pelvis = model_.restJoints(track.previous_c.shape)[0];
    *start = bodyToWorld(track.previous_c, T_now_previous, rest_pelvis);
    if (track.shapeHeld(options_.shape_fits)) start->shape = track.shape();
    if (startsNearThePerson(*start, input.points_c)) input.previous = start;
  }
  return input;
}

// Whether the warm start's pelvis lies within max_start_depth_gap (in depth) of the median depth of
// the person's points; true without points. A track whose last fit was placed on someone else (two
// people in one detection) or that starts again after a gap would otherwise pull this fit, through
// the start and the temporal term, to where the person is not (pf2_synth static seed 3: fits 15 cm
// off for 100 frames).
bool BodyTrackFitter::startsNearThePerson(const BodyParameters& start, const std::vector<Eigen::Vector3d>& points_c) const {
  if (points_c.empty() || options_.max_start_depth_gap <= 0) return true;
  const double pelvis_depth = (start.translation + model_.restJoints(start.shape)[0]).z();
  return std::abs(pelvis_depth - medianDepth(points_c)) <= options_.max_start_depth_gap;
}

// True without points, or where a check finds nothing to measure (no segment with both ends, no
// torso side in full view).
bool BodyTrackFitter::poseFitsTheDepth(const BodyFitInput& input, const CameraIntrinsics& K) const {
  if (input.points_c.empty()) return true;
  const double depth = medianDepth(input.points_c);
  const double confidence = options_.fitter.min_confidence;
  if (options_.min_pose_size > 0) {
    const double size = longestBodySegment(input.keypoints, depth, K, confidence);
    if (size > 0.0 && size < options_.min_pose_size) return false;
  }
  if (options_.min_torso_side > 0) {
    const double side = shortestTorsoSide(input.keypoints, depth, K, confidence, options_.fitter.edge_band);
    if (side > 0.0 && side < options_.min_torso_side) return false;
  }
  return true;
}

void BodyTrackFitter::fitOne(const BodyObservation& o) {
  TrackState& track = tracks_[o.track_id];
  BodyParameters start;
  const BodyFitInput input = fitInput(o, track, &start);
  if (!poseFitsTheDepth(input, o.intrinsics)) return;  // someone else's pose, or a squeezed one
  // The shape is held only where the start carries it (a warm start); otherwise the shape prior.
  const bool hold_shape = input.previous && track.shapeHeld(options_.shape_fits);
  BodyFitResult result;
  {
    ScopedStageTimer timer(&stats_, "fit");
    result = (hold_shape ? fixed_shape_fitter_ : fitter_).fit(input, o.intrinsics);
  }
  if (!result.valid) return;
  if (!track.shapeHeld(options_.shape_fits)) {
    Eigen::VectorXd shape = Eigen::VectorXd::Zero(BodyFitter::Options::kShapeCount);
    const Eigen::Index n = std::min<Eigen::Index>(shape.size(), result.parameters.shape.size());
    shape.head(n) = result.parameters.shape.head(n);
    track.shape_sum += shape;
    ++track.shape_fits;
  }
  track.has_previous = true;
  track.previous_c = result.parameters;
  track.T_w_c_previous = o.T_w_c;
  track.previous_time = o.timestamp;
  fits_.push_back({o.track_id, o.frame_index, o.timestamp, o.keyframe_id, o.T_k_c, result.parameters, result.cost});
}

}  // namespace pf2
