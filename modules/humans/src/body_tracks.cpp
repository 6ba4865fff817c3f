#include "pf2/humans/body_tracks.h"

#include <algorithm>
#include <cmath>

#include "pf2/humans/visible_centre.h"
#include "pf2/core/median.h"

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

// A fit's body with at least this share of its vertices inside its frame's image counts as whole
// in view (its eq. 2 centre then lies where it would without the border); below, as cut by the
// border.
constexpr double kWholeShare = 0.9;

// s: a fit is judged against the line between its neighbouring fits only when these lie at most
// this far apart; over longer spans a walking person's curve leaves the chord by decimetres too.
constexpr double kPathSpan = 1.0;
// Views within Options::cut_bias_window of a cut fit that make a median of their own.
constexpr size_t kNearbyFits = 3;
// m/s: neighbouring fits further apart than a brisk walk covers are no path to judge a fit by: the
// track jumps there (a wrong fit on one side, or the track taken over by another person), and the
// fits on one side would be dropped one by one.
constexpr double kMaxPelvisSpeed = 2.5;

// Standard deviations (Options::centre_sigma and the extrapolation's together) beyond which a
// frame's eq. 2 centre is not believed over the track's extrapolation.
constexpr double kCentreGate = 3.0;

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
                                                    const CameraIntrinsics& intrinsics,
                                                    const Eigen::Vector3d& up_w) const {
  std::map<int, std::vector<const PersonSighting*>> seen;
  std::map<int, std::vector<const BodyTrackFit*>> fitted;
  for (const PersonSighting& s : sightings) seen[s.track_id].push_back(&s);
  for (const BodyTrackFit& f : fits) fitted[f.track_id].push_back(&f);
  const Eigen::Vector3d up = up_w.norm() > 0 ? Eigen::Vector3d(up_w.normalized()) : Eigen::Vector3d::Zero();
  std::vector<BodyTrack> tracks;
  for (auto& [id, list] : seen) {
    std::stable_sort(list.begin(), list.end(),
                     [](const PersonSighting* a, const PersonSighting* b) { return a->frame_index < b->frame_index; });
    std::vector<const BodyTrackFit*>& own = fitted[id];
    std::stable_sort(own.begin(), own.end(),
                     [](const BodyTrackFit* a, const BodyTrackFit* b) { return a->frame_index < b->frame_index; });
    tracks.push_back(assembleTrack(id, list, own, keyframe_poses, intrinsics, up));
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

namespace {

// Keeps the elements of *values whose flag in `keep` is set, in order.
template <typename T>
void keepWhere(const std::vector<bool>& keep, std::vector<T>* values) {
  size_t kept = 0;
  for (size_t i = 0; i < values->size(); ++i) {
    if (keep[i]) (*values)[kept++] = (*values)[i];
  }
  values->resize(kept);
}

// Keeps the fits whose flag in `keep` is set, in each of the parallel lists (views may be empty).
template <typename View>
void keepFits(const std::vector<bool>& keep, std::vector<BodyParameters>* bodies, std::vector<Eigen::Vector3d>* offsets,
              std::vector<const BodyTrackFit*>* fitted, std::vector<View>* views) {
  keepWhere(keep, bodies);
  keepWhere(keep, offsets);
  keepWhere(keep, fitted);
  if (!views->empty()) keepWhere(keep, views);
}

// Per axis.
Eigen::Vector3d medianVector(const std::vector<Eigen::Vector3d>& vectors) {
  Eigen::Vector3d median;
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> values;
    for (const Eigen::Vector3d& v : vectors) values.push_back(v[axis]);
    median[axis] = upperMedian(&values);
  }
  return median;
}

std::vector<Eigen::Vector3d> rotated(const Eigen::Matrix3d& R, const std::vector<Eigen::Vector3d>& points) {
  std::vector<Eigen::Vector3d> out;
  out.reserve(points.size());
  for (const Eigen::Vector3d& p : points) out.push_back(R * p);
  return out;
}

// How far fit i's pelvis lies off the straight line between fits a and b (a < i < b, at i's time),
// or -1 when a and b are no path to judge by: not apart in time, or further apart than a brisk
// walk (kMaxPelvisSpeed) covers in that time.
double deviationFromChord(const std::vector<const BodyTrackFit*>& fitted, const std::vector<BodyParameters>& bodies,
                          size_t a, size_t i, size_t b) {
  const double before = fitted[a]->timestamp, after = fitted[b]->timestamp;
  if (!(after > before)) return -1.0;
  const Eigen::Vector3d& from = bodies[a].translation;
  const Eigen::Vector3d& to = bodies[b].translation;
  if ((to - from).norm() > kMaxPelvisSpeed * (after - before)) return -1.0;
  const double x = (fitted[i]->timestamp - before) / (after - before);
  return (bodies[i].translation - ((1.0 - x) * from + x * to)).norm();
}

}  // namespace

// Drops the fits that disagree with the track's other fits about where the pelvis lies against the
// measured eq. 2 centre, by more than max_offset_deviation from the median. A fit whose body lies
// in the image (no views, no valid view, or at least kWholeShare of it in view) is judged by the
// offset of its pelvis from the centre, against the median over such fits; a fit whose body is
// cut by the image border, whose centre lies on the part in view, by how far the centre lies from
// the one its body gives there (the view's bias), against the median over the views within
// cut_bias_window of it (all views when there are fewer than kNearbyFits).
void BodyTrackAssembler::dropOutlierFits(std::vector<BodyParameters>* bodies, std::vector<Eigen::Vector3d>* offsets,
                                         std::vector<const BodyTrackFit*>* fitted, std::vector<FitView>* views) const {
  if (offsets->size() < 3) return;  // no majority to judge by
  const auto viewed = [&](size_t i) { return !views->empty() && (*views)[i].valid; };
  const auto cut = [&](size_t i) { return viewed(i) && (*views)[i].share_in_view < kWholeShare; };
  std::vector<Eigen::Vector3d> whole_offsets, biases;
  for (size_t i = 0; i < offsets->size(); ++i) {
    if (!cut(i)) whole_offsets.push_back((*offsets)[i]);
    if (viewed(i)) biases.push_back((*views)[i].bias_c);
  }
  if (whole_offsets.size() < 3) whole_offsets = *offsets;
  const Eigen::Vector3d offset_median = medianVector(whole_offsets);
  const Eigen::Vector3d bias_median = biases.empty() ? Eigen::Vector3d::Zero() : medianVector(biases);
  std::vector<bool> keep(offsets->size());
  for (size_t i = 0; i < offsets->size(); ++i) {
    const Eigen::Vector3d deviation =
        cut(i) ? Eigen::Vector3d((*views)[i].bias_c - nearbyBias(*views, *fitted, i, bias_median))
               : Eigen::Vector3d((*offsets)[i] - offset_median);
    keep[i] = deviation.norm() <= options_.max_offset_deviation;
  }
  spareFitsOnPath(*bodies, *fitted, &keep);
  keepFits(keep, bodies, offsets, fitted, views);
}

// The per-axis median of the biases of the valid views within cut_bias_window of fit i (views and
// fitted in step), when there are at least kNearbyFits of them; else (or with cut_bias_window 0)
// the track's median.
Eigen::Vector3d BodyTrackAssembler::nearbyBias(const std::vector<FitView>& views,
                                               const std::vector<const BodyTrackFit*>& fitted, size_t i,
                                               const Eigen::Vector3d& track_median) const {
  const double window = options_.cut_bias_window, t = fitted[i]->timestamp;
  if (!(window > 0.0)) return track_median;
  // The fits are in time order (assemble() sorts them by frame): the window is a run around i.
  size_t first = i, last = i;
  while (first > 0 && t - fitted[first - 1]->timestamp <= window) --first;
  while (last + 1 < fitted.size() && fitted[last + 1]->timestamp - t <= window) ++last;
  std::vector<Eigen::Vector3d> nearby;
  for (size_t j = first; j <= last; ++j) {
    if (views[j].valid) nearby.push_back(views[j].bias_c);
  }
  return nearby.size() >= kNearbyFits ? medianVector(nearby) : track_median;
}

// A fit the offset rule would drop is kept when its pelvis lies within max_path_deviation of the
// straight line between the nearest fits before and after it that the rule keeps, and those lie
// more than max_gap apart: the fit agrees with the person's path, so its frame's eq. 2 centre is
// what is wrong (another person's pixels in the mask, someone passing in front), and without it the
// frames between would be placed by those centres. Within max_gap the frames are interpolated
// between the fits kept, and a fit the offset rule doubts adds only its noise there. No upper limit
// on the span: a seated person's path is a point however long the centres stay wrong, and a wrong
// fit rarely falls on a walker's chord.
void BodyTrackAssembler::spareFitsOnPath(const std::vector<BodyParameters>& bodies,
                                         const std::vector<const BodyTrackFit*>& fitted, std::vector<bool>* keep) const {
  if (!(options_.max_path_deviation > 0.0)) return;
  const std::vector<bool> judged = *keep;
  const long count = static_cast<long>(judged.size());
  for (long i = 0; i < count; ++i) {
    if (judged[i]) continue;
    long before = i - 1, after = i + 1;
    while (before >= 0 && !judged[before]) --before;
    while (after < count && !judged[after]) ++after;
    if (before < 0 || after >= count) continue;
    if (fitted[after]->timestamp - fitted[before]->timestamp <= options_.max_gap) continue;  // interpolated anyway
    const double deviation = deviationFromChord(fitted, bodies, before, i, after);
    (*keep)[i] = deviation >= 0.0 && deviation <= options_.max_path_deviation;
  }
}

void BodyTrackAssembler::dropFitsOffPath(std::vector<BodyParameters>* bodies, std::vector<Eigen::Vector3d>* offsets,
                                         std::vector<const BodyTrackFit*>* fitted,
                                         std::vector<FitView>* views) const {
  if (!(options_.max_path_deviation > 0.0)) return;
  for (;;) {
    double worst = options_.max_path_deviation;
    size_t worst_fit = 0;  // 0: none (the first fit has no neighbour before it)
    for (size_t i = 1; i + 1 < fitted->size(); ++i) {
      if ((*fitted)[i + 1]->timestamp - (*fitted)[i - 1]->timestamp > kPathSpan) continue;
      const double deviation = deviationFromChord(*fitted, *bodies, i - 1, i, i + 1);
      if (deviation > worst) {
        worst = deviation;
        worst_fit = i;
      }
    }
    if (worst_fit == 0) return;
    std::vector<bool> keep(fitted->size(), true);
    keep[worst_fit] = false;
    keepFits(keep, bodies, offsets, fitted, views);
  }
}

std::vector<Eigen::Vector3d> BodyTrackAssembler::verticesAboutPelvis(const BodyParameters& body_w,
                                                                     const Eigen::Vector3d& rest_pelvis) const {
  const Eigen::Vector3d pelvis_w = rest_pelvis + body_w.translation;
  const BodyMesh mesh = model_.evaluate(body_w);
  std::vector<Eigen::Vector3d> relative_w;
  relative_w.reserve(mesh.vertices.size() / kVertexStride + 1);
  for (size_t v = 0; v < mesh.vertices.size(); v += kVertexStride) {
    relative_w.push_back(mesh.vertices[v].cast<double>() - pelvis_w);
  }
  return relative_w;
}

BodyTrackAssembler::FitView BodyTrackAssembler::fitView(const BodyParameters& body_w,
                                                        const Eigen::Vector3d& rest_pelvis,
                                                        const PersonSighting& own, const Eigen::Isometry3d& T_w_c,
                                                        const VisibleCentre& image) const {
  FitView view;
  const Eigen::Vector3d pelvis_w = rest_pelvis + body_w.translation;
  // How far the measured centre lies from the one the body gives (the mask's edges, the depth
  // interval, pixels against vertices), to be allowed for in other frames.
  Eigen::Vector3d modelled;
  view.valid = image.centre(rotated(T_w_c.linear().transpose(), verticesAboutPelvis(body_w, rest_pelvis)),
                            T_w_c.inverse() * pelvis_w, &modelled, &view.share_in_view);
  if (view.valid) view.bias_c = own.p_c - modelled;
  return view;
}

bool BodyTrackAssembler::pelvisByVisibleCentre(const PersonSighting& s, const Eigen::Isometry3d& T_w_c,
                                               const FitView& view, const std::vector<Eigen::Vector3d>& relative_w,
                                               const Eigen::Vector3d& start_w, const VisibleCentre& image,
                                               Eigen::Vector3d* pelvis_w) const {
  Eigen::Vector3d pelvis_c;
  if (!view.valid || !image.pelvisFor(rotated(T_w_c.linear().transpose(), relative_w), s.p_c - view.bias_c,
                                      T_w_c.inverse() * start_w, &pelvis_c)) {
    return false;
  }
  *pelvis_w = T_w_c * pelvis_c;
  return true;
}

bool BodyTrackAssembler::trackVelocity(const std::vector<const BodyTrackFit*>& fitted,
                                       const std::vector<BodyParameters>& bodies, size_t end, int step,
                                       Eigen::Vector3d* velocity) const {
  if (!(options_.velocity_span > 0.0)) return false;
  for (long k = static_cast<long>(end) + step; k >= 0 && k < static_cast<long>(fitted.size()); k += step) {
    const double dt = fitted[k]->timestamp - fitted[end]->timestamp;
    if (std::abs(dt) < options_.velocity_span) continue;
    if (std::abs(dt) > options_.max_gap) break;
    *velocity = (bodies[k].translation - bodies[end].translation) / dt;
    return true;
  }
  return false;
}

Eigen::Vector3d BodyTrackAssembler::translationBetweenFits(const std::vector<const BodyTrackFit*>& fitted,
                                                           const std::vector<BodyParameters>& bodies, size_t a,
                                                           double x) const {
  const size_t b = a + 1;
  const double duration = fitted[b]->timestamp - fitted[a]->timestamp;
  if (!(duration > 0.0)) return bodies[a].translation;
  // Without a velocity beyond an end, the chord's: with both, the curve is the straight line.
  const Eigen::Vector3d chord = (bodies[b].translation - bodies[a].translation) / duration;
  Eigen::Vector3d va = chord, vb = chord;
  trackVelocity(fitted, bodies, a, -1, &va);
  trackVelocity(fitted, bodies, b, +1, &vb);
  const double x2 = x * x, x3 = x2 * x;
  return (2 * x3 - 3 * x2 + 1) * bodies[a].translation + (x3 - 2 * x2 + x) * duration * va +
         (3 * x2 - 2 * x3) * bodies[b].translation + (x3 - x2) * duration * vb;
}

Eigen::Vector3d BodyTrackAssembler::extrapolatedTowardsCentre(const Eigen::Vector3d& extrapolated_w,
                                                              const Eigen::Vector3d& by_centre_w, double since) const {
  const double centre_sigma = options_.centre_sigma;
  if (!(centre_sigma > 0.0)) return extrapolated_w;
  const double drift = 0.5 * options_.extrapolation_acceleration * since * since;
  const double variance = drift * drift + centre_sigma * centre_sigma;
  const Eigen::Vector3d towards_centre = by_centre_w - extrapolated_w;
  // A centre further off than three standard deviations of the two together is a wrong one (a
  // sliver of the person in view, another's pixels in the mask), not a change of pace.
  if (towards_centre.squaredNorm() > kCentreGate * kCentreGate * variance) return extrapolated_w;
  return extrapolated_w + (drift * drift / variance) * towards_centre;
}

BodyTrack BodyTrackAssembler::assembleTrack(int id, const std::vector<const PersonSighting*>& seen,
                                            std::vector<const BodyTrackFit*> fitted,
                                            const std::map<int, Eigen::Isometry3d>& keyframe_poses,
                                            const CameraIntrinsics& intrinsics, const Eigen::Vector3d& up_w) const {
  BodyTrack track;
  track.id = id;
  track.shape = Eigen::VectorXd::Zero(BodyFitter::Options::kShapeCount);
  for (const BodyTrackFit* f : fitted) track.shape += paddedShape(f->body_c.shape);
  if (!fitted.empty()) track.shape /= static_cast<double>(fitted.size());
  const Eigen::Vector3d rest_pelvis = model_.restJoints(track.shape)[0];
  const auto T_w_c = [&](const PersonSighting& s) { return keyframe_poses.at(s.keyframe_id) * s.T_k_c; };
  const auto centre_w = [&](const PersonSighting& s) { return Eigen::Vector3d(T_w_c(s) * s.p_c); };
  const VisibleCentre image(intrinsics);
  // Each fit in the world, with the offset of its pelvis from its frame's eq. 2 centre and, with
  // visible_centre, its view in its own frame.
  std::vector<BodyParameters> bodies;
  std::vector<Eigen::Vector3d> offsets;
  std::vector<FitView> views;
  for (const BodyTrackFit* f : fitted) {
    bodies.push_back(fitInWorld(*f, track.shape, keyframe_poses));
    const auto own = std::find_if(seen.begin(), seen.end(),
                                  [&](const PersonSighting* s) { return s->frame_index == f->frame_index; });
    const Eigen::Vector3d pelvis = rest_pelvis + bodies.back().translation;
    offsets.push_back(own != seen.end() ? Eigen::Vector3d(pelvis - centre_w(**own)) : Eigen::Vector3d::Zero());
    if (!options_.visible_centre) continue;
    views.push_back(own != seen.end() ? fitView(bodies.back(), rest_pelvis, **own, T_w_c(**own), image) : FitView());
  }
  dropOutlierFits(&bodies, &offsets, &fitted, &views);
  dropFitsOffPath(&bodies, &offsets, &fitted, &views);
  // The meshes of the fits that place frames far from every fit, made when first needed.
  std::map<size_t, std::vector<Eigen::Vector3d>> vertices_of_fit;
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
      body.translation = translationBetweenFits(fitted, bodies, next - 1, before / (before + after));
    } else if (!fitted.empty()) {  // the nearest fit's pose, at the eq. 2 centre or moved on with the track
      const size_t nearest = before <= after ? next - 1 : next;
      body = bodies[nearest];
      const Eigen::Vector3d fit_pelvis = rest_pelvis + bodies[nearest].translation;
      const Eigen::Vector3d by_offset = centre_w(*s) + offsets[nearest];
      Eigen::Vector3d pelvis_w = by_offset;
      if (!views.empty() && views[nearest].valid) {
        auto vertices = vertices_of_fit.find(nearest);
        if (vertices == vertices_of_fit.end()) {
          vertices = vertices_of_fit.emplace(nearest, verticesAboutPelvis(bodies[nearest], rest_pelvis)).first;
        }
        pelvisByVisibleCentre(*s, T_w_c(*s), views[nearest], vertices->second, by_offset, image, &pelvis_w);
      }
      if (options_.hold_height && up_w.norm() > 0) pelvis_w += (fit_pelvis - pelvis_w).dot(up_w) * up_w;
      const double since = t - fitted[nearest]->timestamp;
      Eigen::Vector3d velocity;
      if ((next == 0 || next == fitted.size()) && std::abs(since) <= options_.max_extrapolation &&
          trackVelocity(fitted, bodies, nearest, next == 0 ? +1 : -1, &velocity)) {
        pelvis_w = extrapolatedTowardsCentre(fit_pelvis + since * velocity, pelvis_w, std::abs(since));
      }
      placePelvis(pelvis_w, rest_pelvis, &body);
    } else {
      body = standingBody(track.shape);
      body.pose[0] = axisAngle(humanToWorld(T_w_c(*s), centre_w(*s)).linear());
      placePelvis(centre_w(*s), rest_pelvis, &body);
    }
    track.frames.push_back(frameFromBody(t, exact, body));
  }
  track.fits = static_cast<int>(fitted.size());
  smoothPose(&track);
  smoothPelvis(&track);
  return track;
}

namespace {

// Calls visit(j, w) for every frame j within 3 sigma of frame i, w = exp(-dt^2 / (2 sigma^2)).
// Frames are in time order; *first is the first frame within reach of frame i, moved on as i
// grows (start it at 0 and call with i = 0, 1, ...).
template <typename Visit>
void forGaussianNeighbours(const std::vector<BodyTrackFrame>& frames, size_t i, double sigma, size_t* first,
                           const Visit& visit) {
  while (frames[i].timestamp - frames[*first].timestamp > 3 * sigma) ++*first;
  for (size_t j = *first; j < frames.size() && frames[j].timestamp - frames[i].timestamp <= 3 * sigma; ++j) {
    const double dt = frames[j].timestamp - frames[i].timestamp;
    visit(j, std::exp(-0.5 * dt * dt / (sigma * sigma)));
  }
}

}  // namespace

// Gaussian smoothing of every joint's rotation, the root's included, over the track's frames
// within 3 sigma: the weighted mean of the unit quaternions, each turned to the same hemisphere as
// the frame's own (close rotations average well this way). The pelvis stays: a joint's rotation
// does not move it.
void BodyTrackAssembler::smoothPose(BodyTrack* track) const {
  const double sigma = options_.pose_smoothing_sigma;
  if (sigma <= 0) return;
  std::vector<BodyTrackFrame>& frames = track->frames;
  std::vector<std::array<Eigen::Vector4d, kBodyJointCount>> rotations(frames.size());
  for (size_t i = 0; i < frames.size(); ++i) {
    for (int j = 0; j < kBodyJointCount; ++j) rotations[i][j] = quaternion(frames[i].body_w.pose[j]).coeffs();
  }
  std::vector<BodyParameters> smoothed(frames.size());
  size_t first = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    std::array<Eigen::Vector4d, kBodyJointCount> sum;
    sum.fill(Eigen::Vector4d::Zero());
    forGaussianNeighbours(frames, i, sigma, &first, [&](size_t k, double w) {
      for (int j = 0; j < kBodyJointCount; ++j) {
        const Eigen::Vector4d& q = rotations[k][j];
        sum[j] += (q.dot(rotations[i][j]) < 0 ? -w : w) * q;
      }
    });
    smoothed[i] = frames[i].body_w;
    for (int j = 0; j < kBodyJointCount; ++j) {
      smoothed[i].pose[j] = axisAngle(Eigen::Quaterniond(sum[j].normalized()).toRotationMatrix());
    }
  }
  for (size_t i = 0; i < frames.size(); ++i) {
    frames[i] = frameFromBody(frames[i].timestamp, frames[i].fitted, smoothed[i]);
  }
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
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double weights = 0;
    forGaussianNeighbours(frames, i, sigma, &first, [&](size_t j, double w) {
      sum += w * frames[j].pelvis_w;
      weights += w;
    });
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
