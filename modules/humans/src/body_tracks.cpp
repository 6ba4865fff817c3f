#include "pf2/humans/body_tracks.h"

#include <algorithm>
#include <cmath>

#include "pf2/humans/visible_centre.h"

namespace pf2 {

namespace {

Eigen::Quaterniond quaternion(const Eigen::Vector3d& axis_angle) {
  const double angle = axis_angle.norm();
  if (angle < 1e-12) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis_angle / angle));
}

Eigen::Vector3d axisAngle(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd a(R);
  return a.angle() * a.axis();
}

// The first shape coefficients of `shape`, padded with zeros to the fitter's count.
Eigen::VectorXd paddedShape(const Eigen::VectorXd& shape) {
  Eigen::VectorXd out = Eigen::VectorXd::Zero(BodyFitter::Options::kShapeCount);
  const Eigen::Index n = std::min<Eigen::Index>(out.size(), shape.size());
  out.head(n) = shape.head(n);
  return out;
}

// Every n-th mesh vertex stands for the body's outline in VisibleCentre (the mesh's 13 380 vertices
// lie about 1 cm apart; every 4th still covers each pixel cell at the usual distances).
constexpr size_t kVertexStride = 4;

// A person standing with the arms down, as eq. 4 places a person with no fit.
BodyParameters standingBody(const Eigen::VectorXd& shape) {
  BodyParameters body;
  body.shape = shape;
  body.pose[16] = Eigen::Vector3d(0, 0, -1.2);  // left shoulder: arm down
  body.pose[17] = Eigen::Vector3d(0, 0, 1.2);   // right shoulder: arm down
  return body;
}

// The body moved so that its pelvis lies at pelvis_w (the root rotates about the rest pelvis).
void placePelvis(const Eigen::Vector3d& pelvis_w, const Eigen::Vector3d& rest_pelvis, BodyParameters* body) {
  body->translation = pelvis_w - rest_pelvis;
}

}  // namespace

BodyParameters interpolateBodies(const BodyParameters& a, const BodyParameters& b, double t) {
  BodyParameters out = a;
  for (int j = 0; j < kBodyJointCount; ++j) {
    out.pose[j] = axisAngle(quaternion(a.pose[j]).slerp(t, quaternion(b.pose[j])).toRotationMatrix());
  }
  out.translation = (1.0 - t) * a.translation + t * b.translation;
  return out;
}

std::vector<HumanTrack> pelvisTracks(const std::vector<BodyTrack>& bodies) {
  std::vector<HumanTrack> tracks;
  for (const BodyTrack& body : bodies) {
    HumanTrack track;
    track.id = body.id;
    for (const BodyTrackFrame& frame : body.frames) track.points.push_back({frame.timestamp, frame.pelvis_w});
    tracks.push_back(std::move(track));
  }
  return tracks;
}

std::vector<BodyTrack> BodyTrackAssembler::assemble(const std::vector<PersonSighting>& sightings,
                                                    const std::vector<BodyTrackFit>& fits,
                                                    const std::map<int, Eigen::Isometry3d>& keyframe_poses,
                                                    const CameraIntrinsics& intrinsics) const {
  std::map<int, std::vector<const PersonSighting*>> seen;
  std::map<int, std::vector<const BodyTrackFit*>> fitted;
  for (const PersonSighting& s : sightings) seen[s.track_id].push_back(&s);
  for (const BodyTrackFit& f : fits) fitted[f.track_id].push_back(&f);
  std::vector<BodyTrack> tracks;
  for (auto& [id, list] : seen) {
    std::stable_sort(list.begin(), list.end(),
                     [](const PersonSighting* a, const PersonSighting* b) { return a->frame_index < b->frame_index; });
    std::vector<const BodyTrackFit*>& own = fitted[id];
    std::stable_sort(own.begin(), own.end(),
                     [](const BodyTrackFit* a, const BodyTrackFit* b) { return a->frame_index < b->frame_index; });
    tracks.push_back(assembleTrack(id, list, own, keyframe_poses, intrinsics));
  }
  return tracks;
}

BodyParameters BodyTrackAssembler::fitInWorld(const BodyTrackFit& fit, const Eigen::VectorXd& shape,
                                              const std::map<int, Eigen::Isometry3d>& keyframe_poses) const {
  const Eigen::Isometry3d T_w_c = keyframe_poses.at(fit.keyframe_id) * fit.T_k_c;
  const Eigen::Vector3d fit_rest_pelvis = model_.restJoints(fit.body_c.shape)[0];
  BodyParameters body_w = bodyToWorld(fit.body_c, T_w_c, fit_rest_pelvis);
  // The track's shape instead of this fit's, the pelvis kept where the fit put it.
  const Eigen::Vector3d pelvis_w = fit_rest_pelvis + body_w.translation;
  body_w.shape = shape;
  placePelvis(pelvis_w, model_.restJoints(shape)[0], &body_w);
  return body_w;
}

BodyTrackFrame BodyTrackAssembler::frameFromBody(double timestamp, bool fitted, const BodyParameters& body_w) const {
  BodyTrackFrame frame;
  frame.timestamp = timestamp;
  frame.fitted = fitted;
  frame.body_w = body_w;
  frame.joints_w = model_.posedJoints(body_w);
  frame.pelvis_w = frame.joints_w[0];
  frame.T_w_h.linear() = quaternion(body_w.pose[0]).toRotationMatrix();
  frame.T_w_h.translation() = frame.pelvis_w;
  return frame;
}

// Drops the fits whose offset from their eq. 2 centre is far from the median offset of the track's fits.
void BodyTrackAssembler::dropOutlierFits(std::vector<BodyParameters>* bodies, std::vector<Eigen::Vector3d>* offsets,
                                         std::vector<const BodyTrackFit*>* fitted) const {
  if (offsets->size() < 3) return;  // no majority to judge by
  Eigen::Vector3d median;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> values;
    for (const Eigen::Vector3d& o : *offsets) values.push_back(o[axis]);
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    median[axis] = values[values.size() / 2];
  }
  size_t kept = 0;
  for (size_t i = 0; i < offsets->size(); ++i) {
    if (((*offsets)[i] - median).norm() > options_.max_offset_deviation) continue;
    (*bodies)[kept] = (*bodies)[i];
    (*offsets)[kept] = (*offsets)[i];
    (*fitted)[kept] = (*fitted)[i];
    ++kept;
  }
  bodies->resize(kept);
  offsets->resize(kept);
  fitted->resize(kept);
}

// What placing a track's frames by their visible centre needs: the track's fits in the world and
// its sightings, the final keyframe poses, the image model, and per fit (made when first needed)
// its mesh about its pelvis with the bias of its frame's measured centre from the modelled one.
struct BodyTrackAssembler::Placement {
  struct FitView {
    bool valid = false;
    std::vector<Eigen::Vector3d> relative_w;  // every kVertexStride-th vertex minus the pelvis
    Eigen::Vector3d bias_c = Eigen::Vector3d::Zero();  // measured minus modelled centre, camera axes
  };
  const std::vector<BodyParameters>& bodies;
  const std::vector<const BodyTrackFit*>& fitted;
  const std::vector<const PersonSighting*>& seen;
  const std::map<int, Eigen::Isometry3d>& keyframe_poses;
  VisibleCentre image;
  Eigen::Vector3d rest_pelvis;
  std::map<size_t, FitView> views;

  Eigen::Isometry3d T_w_c(const PersonSighting& s) const { return keyframe_poses.at(s.keyframe_id) * s.T_k_c; }
  static std::vector<Eigen::Vector3d> rotated(const Eigen::Matrix3d& R, const std::vector<Eigen::Vector3d>& points) {
    std::vector<Eigen::Vector3d> out;
    out.reserve(points.size());
    for (const Eigen::Vector3d& p : points) out.push_back(R * p);
    return out;
  }
};

bool BodyTrackAssembler::pelvisByVisibleCentre(const PersonSighting& s, size_t nearest, const Eigen::Vector3d& start_w,
                                               Placement* placement, Eigen::Vector3d* pelvis_w) const {
  auto view = placement->views.find(nearest);
  if (view == placement->views.end()) {
    view = placement->views.emplace(nearest, Placement::FitView()).first;
    Placement::FitView& made = view->second;
    const BodyTrackFit& fit = *placement->fitted[nearest];
    const auto own = std::find_if(placement->seen.begin(), placement->seen.end(),
                                  [&](const PersonSighting* p) { return p->frame_index == fit.frame_index; });
    if (own == placement->seen.end()) return false;
    const BodyParameters& body = placement->bodies[nearest];
    const Eigen::Vector3d pelvis = placement->rest_pelvis + body.translation;
    const BodyMesh mesh = model_.evaluate(body);
    for (size_t v = 0; v < mesh.vertices.size(); v += kVertexStride) {
      made.relative_w.push_back(mesh.vertices[v].cast<double>() - pelvis);
    }
    // The fit's own frame: how far its measured centre lies from the one its body gives (the
    // mask's edges, the depth interval, pixels against vertices), to be allowed for elsewhere.
    const Eigen::Isometry3d T_w_c = placement->T_w_c(**own);
    Eigen::Vector3d modelled;
    if (!placement->image.centre(Placement::rotated(T_w_c.linear().transpose(), made.relative_w),
                                 T_w_c.inverse() * pelvis, &modelled)) {
      return false;
    }
    made.bias_c = (*own)->p_c - modelled;
    made.valid = true;
  }
  if (!view->second.valid) return false;
  const Eigen::Isometry3d T_w_c = placement->T_w_c(s);
  Eigen::Vector3d pelvis_c;
  if (!placement->image.pelvisFor(Placement::rotated(T_w_c.linear().transpose(), view->second.relative_w),
                                  s.p_c - view->second.bias_c, T_w_c.inverse() * start_w, &pelvis_c)) {
    return false;
  }
  *pelvis_w = T_w_c * pelvis_c;
  return true;
}

BodyTrack BodyTrackAssembler::assembleTrack(int id, const std::vector<const PersonSighting*>& seen,
                                            std::vector<const BodyTrackFit*> fitted,
                                            const std::map<int, Eigen::Isometry3d>& keyframe_poses,
                                            const CameraIntrinsics& intrinsics) const {
  BodyTrack track;
  track.id = id;
  track.shape = Eigen::VectorXd::Zero(BodyFitter::Options::kShapeCount);
  for (const BodyTrackFit* f : fitted) track.shape += paddedShape(f->body_c.shape);
  if (!fitted.empty()) track.shape /= static_cast<double>(fitted.size());
  const Eigen::Vector3d rest_pelvis = model_.restJoints(track.shape)[0];
  const auto centre_w = [&](const PersonSighting& s) {
    return Eigen::Vector3d(keyframe_poses.at(s.keyframe_id) * s.T_k_c * s.p_c);
  };
  // Each fit in the world, with the offset of its pelvis from its frame's eq. 2 centre.
  std::vector<BodyParameters> bodies;
  std::vector<Eigen::Vector3d> offsets;
  for (const BodyTrackFit* f : fitted) {
    bodies.push_back(fitInWorld(*f, track.shape, keyframe_poses));
    const auto own = std::find_if(seen.begin(), seen.end(),
                                  [&](const PersonSighting* s) { return s->frame_index == f->frame_index; });
    const Eigen::Vector3d pelvis = rest_pelvis + bodies.back().translation;
    offsets.push_back(own != seen.end() ? Eigen::Vector3d(pelvis - centre_w(**own)) : Eigen::Vector3d::Zero());
  }
  dropOutlierFits(&bodies, &offsets, &fitted);
  Placement placement{bodies, fitted, seen, keyframe_poses, VisibleCentre(intrinsics), rest_pelvis, {}};
  size_t next = 0;  // first fit at or after the current frame
  for (const PersonSighting* s : seen) {
    while (next < fitted.size() && fitted[next]->frame_index < s->frame_index) ++next;
    const bool exact = next < fitted.size() && fitted[next]->frame_index == s->frame_index;
    const double t = s->timestamp;
    const double after = next < fitted.size() ? fitted[next]->timestamp - t : INFINITY;
    const double before = next > 0 ? t - fitted[next - 1]->timestamp : INFINITY;
    BodyParameters body;
    if (exact) {
      body = bodies[next];
    } else if (before + after <= options_.max_gap) {
      body = interpolateBodies(bodies[next - 1], bodies[next], before / (before + after));
    } else if (!fitted.empty()) {  // the nearest fit's pose, moved with the eq. 2 centre
      const size_t nearest = before <= after ? next - 1 : next;
      body = bodies[nearest];
      const Eigen::Vector3d by_offset = centre_w(*s) + offsets[nearest];
      Eigen::Vector3d pelvis_w = by_offset;
      if (options_.visible_centre) pelvisByVisibleCentre(*s, nearest, by_offset, &placement, &pelvis_w);
      placePelvis(pelvis_w, rest_pelvis, &body);
    } else {
      body = standingBody(track.shape);
      const Eigen::Isometry3d T_w_h =
          humanToWorld(keyframe_poses.at(s->keyframe_id) * s->T_k_c, centre_w(*s));
      body.pose[0] = axisAngle(T_w_h.linear());
      placePelvis(centre_w(*s), rest_pelvis, &body);
    }
    track.frames.push_back(frameFromBody(t, exact, body));
  }
  track.fits = static_cast<int>(fitted.size());
  smoothPelvis(&track);
  return track;
}

// Gaussian smoothing of the pelvis over the track's frames within 3 sigma; each body (its joints,
// its root frame) moves with its pelvis.
void BodyTrackAssembler::smoothPelvis(BodyTrack* track) const {
  const double sigma = options_.smoothing_sigma;
  if (sigma <= 0) return;
  std::vector<BodyTrackFrame>& frames = track->frames;
  std::vector<Eigen::Vector3d> smoothed(frames.size());
  size_t first = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    while (frames[i].timestamp - frames[first].timestamp > 3 * sigma) ++first;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double weights = 0;
    for (size_t j = first; j < frames.size() && frames[j].timestamp - frames[i].timestamp <= 3 * sigma; ++j) {
      const double dt = frames[j].timestamp - frames[i].timestamp;
      const double w = std::exp(-0.5 * dt * dt / (sigma * sigma));
      sum += w * frames[j].pelvis_w;
      weights += w;
    }
    smoothed[i] = sum / weights;
  }
  for (size_t i = 0; i < frames.size(); ++i) {
    const Eigen::Vector3d shift = smoothed[i] - frames[i].pelvis_w;
    frames[i].body_w.translation += shift;
    for (Eigen::Vector3d& joint : frames[i].joints_w) joint += shift;
    frames[i].pelvis_w = smoothed[i];
    frames[i].T_w_h.translation() = smoothed[i];
  }
}

}  // namespace pf2
