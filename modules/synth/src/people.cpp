#include "pf2/synth/people.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <utility>

#include <Eigen/Geometry>

#include "pf2/core/error.h"
#include "hash_random.h"

namespace pf2 {

namespace {

constexpr double kPi = 3.14159265358979323846;

using synth::HashRng;

double wrapAngle(double a) { return std::atan2(std::sin(a), std::cos(a)); }
double smoothstep(double a) {
  a = std::min(1.0, std::max(0.0, a));
  return a * a * (3.0 - 2.0 * a);
}

Eigen::Vector3d axisAngle(const Eigen::Matrix3d& R) {
  const Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}
Eigen::Matrix3d rotation(const Eigen::Vector3d& axis_angle) {
  const double angle = axis_angle.norm();
  if (angle < 1e-12) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, axis_angle / angle).toRotationMatrix();
}
Eigen::Matrix3d rotX(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix(); }
Eigen::Matrix3d rotZ(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

// Body frame (y up, facing +z) to world (z up) for a heading yaw about world z (0 = facing +x).
Eigen::Matrix3d bodyToWorld(double yaw) { return rotZ(yaw + kPi / 2.0) * rotX(kPi / 2.0); }

// Joint indices (SMPL order).
enum Joint {
  kPelvis = 0, kLeftHip = 1, kRightHip = 2, kSpine1 = 3, kLeftKnee = 4, kRightKnee = 5,
  kSpine2 = 6, kLeftAnkle = 7, kRightAnkle = 8, kSpine3 = 9, kLeftFoot = 10, kRightFoot = 11,
  kNeck = 12, kLeftCollar = 13, kRightCollar = 14, kHead = 15, kLeftShoulder = 16,
  kRightShoulder = 17, kLeftElbow = 18, kRightElbow = 19, kLeftWrist = 20, kRightWrist = 21,
  kLeftHand = 22, kRightHand = 23
};

Eigen::Vector3f bgr(double r, double g, double b) {
  return Eigen::Vector3f(static_cast<float>(b), static_cast<float>(g), static_cast<float>(r));
}

// Clothing, skin, hair and shoe colours by the dominant joint of each vertex.
std::vector<Eigen::Vector3f> clothe(const BodyModel& model, const Eigen::VectorXd& shape, HashRng* rng) {
  static const Eigen::Vector3f kShirts[] = {bgr(0.75, 0.12, 0.12), bgr(0.15, 0.35, 0.7), bgr(0.9, 0.9, 0.88),
                                            bgr(0.2, 0.55, 0.25), bgr(0.85, 0.65, 0.1), bgr(0.45, 0.2, 0.55),
                                            bgr(0.15, 0.15, 0.17), bgr(0.9, 0.45, 0.15)};
  static const Eigen::Vector3f kTrousers[] = {bgr(0.12, 0.18, 0.38), bgr(0.1, 0.1, 0.11), bgr(0.55, 0.48, 0.33),
                                              bgr(0.35, 0.35, 0.37), bgr(0.25, 0.3, 0.5)};
  static const Eigen::Vector3f kSkins[] = {bgr(0.96, 0.8, 0.69), bgr(0.88, 0.67, 0.52), bgr(0.7, 0.5, 0.36),
                                           bgr(0.45, 0.3, 0.2)};
  static const Eigen::Vector3f kHair[] = {bgr(0.08, 0.06, 0.05), bgr(0.3, 0.18, 0.1), bgr(0.75, 0.6, 0.35),
                                          bgr(0.6, 0.6, 0.6)};
  const Eigen::Vector3f shirt = kShirts[rng->integer(0, 7)];
  const Eigen::Vector3f trousers = kTrousers[rng->integer(0, 4)];
  const Eigen::Vector3f skin = kSkins[rng->integer(0, 3)];
  const Eigen::Vector3f hair = kHair[rng->integer(0, 3)];
  const Eigen::Vector3f shoes = bgr(0.12, 0.1, 0.1);
  const bool long_sleeves = rng->uniform(0, 1) < 0.5;
  const std::uint64_t texture_seed = rng->next();

  BodyParameters rest;
  rest.shape = shape;
  const BodyMesh mesh = model.evaluate(rest);
  const Eigen::Vector3d head = mesh.joints[kHead];
  const Eigen::MatrixXf& weights = model.weights();
  std::vector<Eigen::Vector3f> colors(mesh.vertices.size());
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    int joint = 0;
    weights.row(static_cast<Eigen::Index>(i)).maxCoeff(&joint);
    const Eigen::Vector3d p = mesh.vertices[i].cast<double>();
    Eigen::Vector3f c;
    switch (joint) {
      case kHead: {
        // Hair on top and at the back of the head; the face stays skin.
        const bool top = p.y() > head.y() + 0.06;
        const bool back = p.z() < head.z() - 0.01 && p.y() > head.y() - 0.03;
        c = (top || back) ? hair : skin;
        break;
      }
      case kNeck: case kLeftWrist: case kRightWrist: case kLeftHand: case kRightHand:
        c = skin;
        break;
      case kLeftElbow: case kRightElbow:
        c = long_sleeves ? shirt : skin;
        break;
      case kSpine1: case kSpine2: case kSpine3: case kLeftCollar: case kRightCollar:
      case kLeftShoulder: case kRightShoulder:
        c = shirt;
        break;
      case kLeftAnkle: case kRightAnkle: case kLeftFoot: case kRightFoot:
        c = shoes;
        break;
      default:  // pelvis, hips, knees
        c = trousers;
        break;
    }
    // Fabric and skin are not flat: a little per-vertex variation gives features to track.
    const double variation = 0.88 + 0.24 * synth::uniform01(synth::hashOf(texture_seed, i));
    colors[i] = (c * static_cast<float>(variation)).cwiseMin(1.0f);
  }
  return colors;
}

}  // namespace

JointRotations walkingPose(double phase, double amplitude, double arm_lowering) {
  JointRotations r;
  for (auto& v : r) v.setZero();
  const double a = amplitude;
  for (int side = 0; side < 2; ++side) {
    // The right leg is half a cycle behind the left one.
    const double phi = phase + side * kPi;
    const double hip_flexion = a * (0.12 + 0.36 * std::sin(phi));
    const double swing = std::max(0.0, std::cos(phi + 0.3));
    double knee_flexion = 0.08 + 0.95 * std::pow(swing, 1.5);
    const double after_strike = wrapAngle(phi - kPi / 2.0);  // loading response after heel strike
    if (after_strike > 0.0 && after_strike < kPi / 2.0) knee_flexion += 0.2 * std::sin(2.0 * after_strike);
    const double ankle = a * (0.05 - 0.18 * std::sin(phi));
    r[side == 0 ? kLeftHip : kRightHip] = Eigen::Vector3d(-hip_flexion, 0.0, 0.0);
    r[side == 0 ? kLeftKnee : kRightKnee] = Eigen::Vector3d(a * knee_flexion, 0.0, 0.0);
    r[side == 0 ? kLeftAnkle : kRightAnkle] = Eigen::Vector3d(ankle, 0.0, 0.0);
  }
  // Pelvis and spine counter-rotate; arms swing against the legs of their side.
  const double s = std::sin(phase);
  r[kPelvis] = Eigen::Vector3d(0.0, 0.08 * a * s, 0.03 * a * std::cos(phase));
  r[kSpine1] = Eigen::Vector3d(0.03 * a, -0.03 * a * s, 0.0);
  r[kSpine2] = Eigen::Vector3d(0.0, -0.03 * a * s, 0.0);
  r[kSpine3] = Eigen::Vector3d(0.0, -0.02 * a * s, 0.0);
  const double arm_swing = 0.35 * a * s;
  r[kLeftShoulder] = axisAngle(rotX(arm_swing - 0.05) * rotZ(-arm_lowering));
  r[kRightShoulder] = axisAngle(rotX(-arm_swing - 0.05) * rotZ(arm_lowering));
  r[kLeftElbow] = Eigen::Vector3d(0.0, -(0.2 + 0.3 * a * std::max(0.0, -s)), 0.0);
  r[kRightElbow] = Eigen::Vector3d(0.0, 0.2 + 0.3 * a * std::max(0.0, s), 0.0);
  r[kHead] = Eigen::Vector3d(0.03 * a * std::cos(2.0 * phase), 0.0, 0.0);
  return r;
}

JointRotations sittingPose(double arm_lowering) {
  JointRotations r;
  for (auto& v : r) v.setZero();
  r[kLeftHip] = Eigen::Vector3d(-1.5, 0.0, 0.1);
  r[kRightHip] = Eigen::Vector3d(-1.5, 0.0, -0.1);
  r[kLeftKnee] = Eigen::Vector3d(1.45, 0.0, 0.0);
  r[kRightKnee] = Eigen::Vector3d(1.45, 0.0, 0.0);
  r[kLeftAnkle] = Eigen::Vector3d(0.05, 0.0, 0.0);
  r[kRightAnkle] = Eigen::Vector3d(0.05, 0.0, 0.0);
  r[kSpine1] = Eigen::Vector3d(0.06, 0.0, 0.0);
  r[kLeftShoulder] = axisAngle(rotX(-0.2) * rotZ(-arm_lowering));
  r[kRightShoulder] = axisAngle(rotX(-0.2) * rotZ(arm_lowering));
  r[kLeftElbow] = Eigen::Vector3d(0.0, -1.3, 0.0);
  r[kRightElbow] = Eigen::Vector3d(0.0, 1.3, 0.0);
  return r;
}

double armLoweringAngle(const BodyModel& model, const Eigen::VectorXd& shape) {
  const auto joints = model.restJoints(shape);
  const Eigen::Vector3d upper_arm = joints[kLeftElbow] - joints[kLeftShoulder];
  // Angle below the horizontal in the rest pose; hanging arms are about 80 degrees down.
  const double rest_down = std::atan2(-upper_arm.y(), std::abs(upper_arm.x()));
  return 80.0 * kPi / 180.0 - rest_down;
}

RenderMesh bodyRenderMesh(const BodyMesh& mesh, std::vector<Eigen::Vector3f> colors, std::uint16_t label) {
  RenderMesh render;
  render.vertices = mesh.vertices;
  render.triangles = mesh.triangles;
  render.colors = std::move(colors);
  render.label = label;
  render.computeVertexNormals();
  return render;
}

namespace {

// Crossings start and end this far beyond the side edge of the view, so that the whole body (half
// a stride and a swinging arm, about 0.4 m) is out of view there: metres.
constexpr double kOutOfViewMargin = 0.5;
// Free floor a crossing may use (x_min, y_min, x_max, y_max), metres: clear of the shelves along the
// side walls, the boxes in the near corners and the desk.
const Eigen::Vector4d kCrossingFloor(0.5, 0.95, 5.5, 3.2);
// Random actions tried between two crossings of one person; those that would make it late or bring
// it close in front of the camera are dropped.
constexpr int kFillAttempts = 12;
// Random actions tried that would bring a person nearer than min_separation to someone.
constexpr int kApartAttempts = 40;
// Away from crossings a person keeps out of the close zone in front of the camera; checked this
// often along its script, seconds.
constexpr double kClearanceStep = 0.2;
// People keep apart: checked this often along a new action, seconds (two people walking towards
// each other close 0.25 m in that time).
constexpr double kSeparationStep = 0.1;
// A new action also keeps the person apart this long after it ends, standing where it ended, so
// that the next action is not too late to get out of someone's way: seconds.
constexpr double kApartLookahead = 1.0;
// Half the width of a person seen from any side, arms included: metres.
constexpr double kBodyHalfWidth = 0.4;
// The height at which a person is tested against the view: the chest, metres.
constexpr double kChestHeight = 1.2;

bool onFloor(const Eigen::Vector2d& p, const Eigen::Vector4d& floor) {
  return p.x() >= floor[0] && p.y() >= floor[1] && p.x() <= floor[2] && p.y() <= floor[3];
}

Eigen::Vector2d clampToFloor(const Eigen::Vector2d& p, const Eigen::Vector4d& floor) {
  return Eigen::Vector2d(std::min(floor[2], std::max(floor[0], p.x())), std::min(floor[3], std::max(floor[1], p.y())));
}

// How a crossing runs relative to the camera: a V with its tip on the view's axis, the nearest
// point of the path; a bend of 0 is a straight line square to the axis.
struct CrossingShape {
  double nearest = 1.0;  // floor distance from the camera centre to the tip, metres
  double bend = 0.0;     // angle of each half of the V to the image plane, radians, 0 .. 0.8
};

struct CrossingPath {
  Eigen::Vector2d left, tip, right;  // world x y; the ends lie beyond the left and right edge of the view
};

// The walk across the camera's horizontal view with `shape`, from kOutOfViewMargin (measured square
// to the edge) beyond the left edge of the view to as far beyond the right one.
CrossingPath crossingPath(const Eigen::Isometry3d& T_w_c, double half_view_tan, const CrossingShape& shape) {
  Eigen::Vector2d forward = T_w_c.linear().col(2).head<2>();
  // Every camera motion looks into the room (+y) and never straight down; guard all the same.
  forward = forward.norm() > 0.1 ? forward.normalized() : Eigen::Vector2d(0.0, 1.0);
  const Eigen::Vector2d right(forward.y(), -forward.x());
  // In the camera's floor coordinates (x right, z forward) the right half is (0, nearest) +
  // s (cos, sin): it meets the edge x = T z at s = T nearest / (cos - T sin) and moves away from
  // it by (cos - T sin) / sqrt(1 + T^2) per metre walked. The left half mirrors it.
  const double T = half_view_tan;
  // Each half must leave the view through a side edge, not run along it: at least 0.2 rad between them.
  const double bend = std::max(0.0, std::min(shape.bend, std::atan(1.0 / T) - 0.2));
  const double c = std::cos(bend), n = std::sin(bend);
  const double s_end = (T * shape.nearest + kOutOfViewMargin * std::sqrt(1.0 + T * T)) / (c - T * n);
  const Eigen::Vector2d tip = T_w_c.translation().head<2>() + shape.nearest * forward;
  return {tip + s_end * (-c * right + n * forward), tip, tip + s_end * (c * right + n * forward)};
}

// crossingPath, made less bent in 0.05 rad steps and then brought closer to the camera in 5 cm steps
// (not below min_distance) while one of its ends lies off the free floor; ends still off it are
// moved onto it.
CrossingPath crossingPathOnFloor(const Eigen::Isometry3d& T_w_c, double half_view_tan, CrossingShape shape,
                                 double min_distance) {
  CrossingPath path = crossingPath(T_w_c, half_view_tan, shape);
  const auto fits = [&path] { return onFloor(path.left, kCrossingFloor) && onFloor(path.right, kCrossingFloor); };
  while (!fits() && (shape.bend > 0.0 || shape.nearest > min_distance)) {
    if (shape.bend > 0.0) {
      shape.bend = std::max(0.0, shape.bend - 0.05);
    } else {
      shape.nearest = std::max(min_distance, shape.nearest - 0.05);
    }
    path = crossingPath(T_w_c, half_view_tan, shape);
  }
  return {clampToFloor(path.left, kCrossingFloor), path.tip, clampToFloor(path.right, kCrossingFloor)};
}

void checkCloseCrossings(const Crowd::CloseCrossings& close, const Crowd::CameraPath& camera) {
  if (!close.enabled) return;
  if (!(close.min_distance >= 0.3 && close.min_distance <= close.max_distance && close.max_distance <= 3.0)) {
    throw Error("close crossings: min_distance and max_distance must satisfy 0.3 <= min <= max <= 3 m");
  }
  if (!(close.max_bend >= 0.0 && close.max_bend <= 0.8)) {
    throw Error("close crossings: max_bend must lie in 0 .. 0.8 rad");
  }
  if (!(close.look_probability >= 0.0 && close.look_probability <= 1.0 && close.look_time >= 0.0 &&
        close.look_time <= 5.0)) {
    throw Error("close crossings: look_probability must lie in 0 .. 1 and look_time in 0 .. 5 s");
  }
  if (!(close.min_pause >= 0.0 && close.max_pause >= close.min_pause)) {
    throw Error("close crossings: pauses must satisfy 0 <= min_pause <= max_pause (seconds)");
  }
  if (!camera.pose_at || !(camera.half_view_tan > 0.0)) {
    throw Error("close crossings need the camera path (pose_at and a positive half_view_tan)");
  }
}

}  // namespace

// A crossing in the plan: who walks it, from where to where, starting when.
struct Crowd::PlannedCrossing {
  int person = 0;
  Eigen::Vector2d from = Eigen::Vector2d::Zero();  // world x y, out of view
  Eigen::Vector2d tip = Eigen::Vector2d::Zero();   // world x y, the nearest point, in view
  Eigen::Vector2d to = Eigen::Vector2d::Zero();    // world x y, out of view
  double start = 0.0;        // seconds: the walk from `from` over `tip` to `to` begins
  double look = 0.0;         // seconds standing at the tip facing the camera (0: walks on)
  double look_heading = 0.0; // radians about world z: from the tip towards the camera
};

// One person's script as it is written: segments appended one after the other, and where, facing
// where and when the script ends so far.
class Crowd::ScriptWriter {
 public:
  ScriptWriter(const Eigen::Vector2d& position, double yaw, double speed)
      : position_(position), yaw_(yaw), speed_(speed) {}

  double time() const { return t_; }
  const Eigen::Vector2d& position() const { return position_; }
  double yaw() const { return yaw_; }
  double speed() const { return speed_; }
  std::vector<Segment> release() { return std::move(script_); }

  // Where on the floor the person is at time t seconds (at the end of the script after it ends);
  // sitting counts as being at the chair's front edge.
  Eigen::Vector2d positionAt(double t) const {
    const auto it = segmentAt(t);
    if (it == script_.end()) return position_;
    if (it->kind != Segment::Kind::kWalk || !(it->t1 > it->t0)) return it->from;
    const double alpha = std::max(0.0, (t - it->t0) / (it->t1 - it->t0));
    return it->from + alpha * (it->to - it->from);
  }

  // Where on the floor the person's pelvis is at time t seconds: as positionAt, but on the chair
  // while sitting (sitting down and standing up move it between the chair and its front edge).
  Eigen::Vector2d pelvisAt(double t) const {
    const auto it = segmentAt(t);
    if (it == script_.end()) return position_;
    const double alpha = it->t1 > it->t0 ? std::min(1.0, std::max(0.0, (t - it->t0) / (it->t1 - it->t0))) : 1.0;
    switch (it->kind) {
      case Segment::Kind::kWalk: case Segment::Kind::kSitDown:
        return it->from + alpha * (it->to - it->from);
      case Segment::Kind::kSit:
        return it->to;
      case Segment::Kind::kStandUp: {
        // A script's first segment may be the rise from the chair (nothing before it): then from.
        const Eigen::Vector2d seat = it == script_.begin() ? it->from : std::prev(it)->to;
        return seat + alpha * (it->to - seat);
      }
      default:
        return it->from;
    }
  }

  // The segment running at time t seconds (end() after the script ends).
  std::vector<Segment>::const_iterator segmentAt(double t) const {
    return std::upper_bound(script_.begin(), script_.end(), t,
                            [](double value, const Segment& s) { return value < s.t1; });
  }

  Segment* add(Segment::Kind kind, double duration, const Eigen::Vector2d& to, double yaw1) {
    Segment s;
    s.kind = kind;
    s.t0 = t_;
    s.t1 = t_ + duration;
    s.from = position_;
    s.to = to;
    s.yaw0 = yaw_;
    s.yaw1 = yaw1;
    s.distance0 = distance_;
    if (kind == Segment::Kind::kWalk) distance_ += (to - position_).norm();
    if (kind == Segment::Kind::kTurn) distance_ += 0.25 * std::abs(wrapAngle(yaw1 - yaw_));
    script_.push_back(s);
    t_ += duration;
    if (kind != Segment::Kind::kSitDown && kind != Segment::Kind::kSit) position_ = to;
    yaw_ = yaw1;
    return &script_.back();
  }

  // Turns in place to `heading` (radians about world z) at 2.5 rad/s, for at least 0.3 s; nothing
  // when already within 0.05 rad of it.
  void turnTo(double heading) {
    const double turn = std::abs(wrapAngle(heading - yaw_));
    if (turn > 0.05) add(Segment::Kind::kTurn, std::max(0.3, turn / 2.5), position_, yaw_ + wrapAngle(heading - yaw_));
  }

  // Turns towards `target`, then walks straight to it at the person's speed.
  void walkTo(const Eigen::Vector2d& target) {
    const Eigen::Vector2d d = target - position_;
    if (d.norm() < 0.05) return;
    turnTo(std::atan2(d.y(), d.x()));
    add(Segment::Kind::kWalk, d.norm() / speed_, target, yaw_);
  }

  // Stands where the script ends until `time` seconds (nothing when that is under 10 ms away).
  void standUntil(double time) {
    if (time - t_ > 0.01) add(Segment::Kind::kStand, time - t_, position_, yaw_);
  }

 private:
  std::vector<Segment> script_;
  Eigen::Vector2d position_;
  double yaw_ = 0.0;                   // radians about world z
  double speed_ = 1.0;                 // m/s
  double t_ = 0.0;                     // seconds
  double distance_ = 0.0;              // walked so far (gait phase), metres
};

// Writes the people's scripts: a random start, then random actions (walk, stand, sit). With close
// crossings, the crossings of all people are planned first, one after the other, and each
// person's random actions are fitted into the time between its crossings.
class Crowd::ScriptPlanner {
 public:
  ScriptPlanner(const Crowd::Options& options, const StaticScene& scene, const CameraPath& camera)
      : options_(options), scene_(scene), camera_(camera), area_(scene.walkableArea()) {}

  // Where person k starts: a random point and heading; person 1 may start seated at the desk.
  ScriptWriter start(int k, double speed, const std::vector<ScriptWriter>& earlier, HashRng* rng) const {
    Eigen::Vector2d position = randomPoint(rng);
    // Nobody starts where an earlier person comes within min_separation in the first two seconds
    // (as far as their script is written), and with close crossings nobody starts in the close
    // zone (the draws of other sequences stay as they were).
    const auto clear = [&](const Eigen::Vector2d& p) {
      return (!options_.close.enabled || standsClear(p, 0.0, 2.0)) &&
             keepsApart(ScriptWriter(p, 0.0, 1.0), k, earlier, 0.0, 2.0);
    };
    for (int redraw = 0; redraw < 20 && !clear(position); ++redraw) position = randomPoint(rng);
    ScriptWriter writer(position, rng->uniform(-kPi, kPi), speed);
    // With close crossings and one person, that person crosses from the start instead.
    const bool alone_crossing = options_.close.enabled && options_.people == 1;
    if (k == 0 && canSit(k) && options_.first_person_seated && !alone_crossing) {
      // As in TUM fr3/walking_*, someone sits at the desk when the recording starts.
      const StaticScene::Seat& seat = scene_.seats()[0];
      const Eigen::Vector2d in_front =
          seat.position_w.head<2>() + 0.37 * Eigen::Vector2d(std::cos(seat.yaw), std::sin(seat.yaw));
      writer = ScriptWriter(in_front, seat.yaw, speed);
      writer.add(Segment::Kind::kSit, rng->uniform(2.0, 5.0), seat.position_w.head<2>(), seat.yaw)->seat = 0;
      writer.add(Segment::Kind::kStandUp, 1.2, in_front, seat.yaw)->seat = 0;
    }
    return writer;
  }

  // Random actions of person k until its script reaches `time` seconds (see addFittingAction; when
  // none fits, the person stands still for half a second).
  void addRandomActionsUntil(double time, int k, HashRng* rng, std::vector<ScriptWriter>* writers) const {
    ScriptWriter& writer = (*writers)[k];
    while (writer.time() < time) {
      if (!addFittingAction(k, rng, writers)) {
        writer.add(Segment::Kind::kStand, 0.5, writer.position(), writer.yaw());
      }
    }
  }

  // Walks person k 0.8 or 1.6 m away from where its script ends, in the first of eight directions
  // (starting straight ahead) that fits (keeps it apart from the others and out of the close zone);
  // false when none does. The way out when someone walks through the spot where no random action fitted.
  bool stepAside(int k, std::vector<ScriptWriter>* writers) const {
    ScriptWriter& writer = (*writers)[k];
    for (const double distance : {0.8, 1.6}) {
      for (int i = 0; i < 8; ++i) {
        const double heading = writer.yaw() + i * kPi / 4.0;
        const Eigen::Vector2d target =
            clampToFloor(writer.position() + distance * Eigen::Vector2d(std::cos(heading), std::sin(heading)), area_);
        ScriptWriter trial = writer;
        trial.walkTo(target);
        if (trial.time() > writer.time() && fits(trial, k, *writers, writer.time(), trial.time())) {
          writer = trial;
          return true;
        }
      }
    }
    return false;
  }

  // Adds to person k's script a random action that keeps it min_separation away from the others
  // as far as their scripts are written and, with close crossings, out of the close zone. Tries
  // kFillAttempts actions that break the close zone and kApartAttempts that come too near someone
  // (then steps aside); false when nothing fits. Without close crossings, an action that adds
  // nothing (a walk shorter than 0.6 m) is no attempt, so sequences without near people keep their draws.
  bool addFittingAction(int k, HashRng* rng, std::vector<ScriptWriter>* writers) const {
    ScriptWriter& writer = (*writers)[k];
    int zone_misses = 0, crowd_misses = 0;
    while (zone_misses < kFillAttempts && crowd_misses < kApartAttempts) {
      ScriptWriter trial = writer;
      addRandomAction(k, rng, &trial);
      const bool moved = trial.time() > writer.time();
      if (!moved || (options_.close.enabled && !keepsClear(trial, writer.time(), trial.time()))) {
        zone_misses += options_.close.enabled ? 1 : 0;
      } else if (!keepsApart(trial, k, *writers, writer.time(), trial.time())) {
        ++crowd_misses;
      } else {
        writer = trial;
        return true;
      }
    }
    return crowd_misses >= kApartAttempts && stepAside(k, writers);
  }

  // The close crossings of the whole sequence, in time order: each starts a random pause after the
  // previous one ended, walked by the person who crossed least recently among those who can be
  // at its start by then (else by the one who can be there first). The first one is walked by a
  // person who starts the sequence at its start; `starts` is changed for that person.
  std::vector<PlannedCrossing> planCrossings(std::vector<ScriptWriter>* starts) const {
    const Crowd::CloseCrossings& close = options_.close;
    std::vector<ScriptWriter> writers = *starts;
    HashRng rng(synth::hashOf(options_.seed, 0xc105ec055));
    std::vector<double> last_start(writers.size(), -1e9);
    std::vector<PlannedCrossing> plan;
    double next = rng.uniform(0.0, close.max_pause);
    while (!writers.empty() && next < options_.duration) {
      CrossingShape shape;
      // Cubed: near crossings, where a person fills a large part of the image, are the common ones
      // (half of them within the nearest eighth of the range).
      shape.nearest = close.min_distance + (close.max_distance - close.min_distance) * std::pow(rng.uniform(0, 1), 3);
      shape.bend = rng.uniform(0.0, close.max_bend);
      const double look = rng.uniform(0, 1) < close.look_probability ? close.look_time : 0.0;
      const PlannedCrossing crossing = plan.empty() ? openingCrossing(starts, next, shape, look)
                                                    : chooseCrosser(writers, last_start, next, shape, look);
      if (plan.empty()) writers[crossing.person] = (*starts)[crossing.person];
      ScriptWriter& writer = writers[crossing.person];
      if (nearestInView(crossing, writer.speed()) < close.min_distance) {
        // The camera's own motion would bring the person nearer than min_distance and the room
        // has no farther path: try again half a second later.
        next += 0.5;
        continue;
      }
      walkCrossing(crossing, &writer);
      last_start[crossing.person] = crossing.start;
      // The next person may set off while this one is still walking out beyond the view's edge; the
      // pause counts from this one leaving the view to the next one entering it (at most at max_speed).
      const double out_of_view = kOutOfViewMargin / writer.speed() + kOutOfViewMargin / options_.max_speed;
      next = writer.time() - out_of_view + rng.uniform(close.min_pause, close.max_pause);
      plan.push_back(crossing);
    }
    return plan;
  }

  // Random actions that leave the person time to reach the crossing's start and keep it out of
  // the close zone until then, then the crossing.
  void addCrossing(const PlannedCrossing& crossing, HashRng* rng, std::vector<ScriptWriter>* writers) const {
    ScriptWriter* writer = &(*writers)[crossing.person];
    for (int attempt = 0; attempt < kFillAttempts; ++attempt) {
      ScriptWriter trial = *writer;
      addRandomAction(crossing.person, rng, &trial);
      if (arrival(crossing, trial) <= crossing.start &&
          fits(trial, crossing.person, *writers, writer->time(), crossing.start)) {
        *writer = trial;
      }
    }
    // Wait where the last action ended rather than at the edge of the view, unless the camera
    // comes close to that spot meanwhile; then at the crossing's start.
    const double leave = crossing.start - (arrival(crossing, *writer) - writer->time());
    if (standsClear(writer->position(), writer->time(), leave)) writer->standUntil(leave);
    walkCrossing(crossing, writer);
  }

 private:
  bool canSit(int k) const { return k < static_cast<int>(scene_.seats().size()); }

  // The chest of a person standing at `position`, in the camera frame.
  static Eigen::Vector3d chestInCamera(const Eigen::Vector2d& position, const Eigen::Isometry3d& T_w_c) {
    return T_w_c.inverse() * Eigen::Vector3d(position.x(), position.y(), kChestHeight);
  }

  // Whether some of a person with its chest at `chest_c` (camera frame) is in the horizontal view.
  bool inView(const Eigen::Vector3d& chest_c) const {
    return std::abs(chest_c.x()) - kBodyHalfWidth <= std::max(0.0, chest_c.z()) * camera_.half_view_tan;
  }

  // Whether a person standing at `position` at time t seconds is out of the close zone: out of the
  // camera's view (whole body) or at least max_distance in front of it. Only crossings come closer.
  bool clearOfCloseZone(const Eigen::Vector2d& position, double t) const {
    const Eigen::Vector3d chest_c = chestInCamera(position, camera_.pose_at(t));
    return chest_c.z() >= options_.close.max_distance || !inView(chest_c);
  }

  // Whether a person standing at `position` stays out of the close zone from `from` to `until` seconds.
  bool standsClear(const Eigen::Vector2d& position, double from, double until) const {
    return keepsClear(ScriptWriter(position, 0.0, 1.0), from, until);
  }

  // Whether the person of `script` stays out of the close zone from `from` to `until` seconds.
  bool keepsClear(const ScriptWriter& script, double from, double until) const {
    for (double t = from; t <= until; t += kClearanceStep) {
      if (!clearOfCloseZone(script.positionAt(t), t)) return false;
    }
    return true;
  }

  // Whether person k, following `script`, keeps min_separation from every other person of
  // `writers` from `from` to kApartLookahead past `until` seconds, as far as their scripts are written.
  bool keepsApart(const ScriptWriter& script, int k, const std::vector<ScriptWriter>& writers, double from,
                  double until) const {
    if (!(options_.min_separation > 0.0)) return true;
    for (double t = from; t <= until + kApartLookahead; t += kSeparationStep) {
      for (size_t j = 0; j < writers.size(); ++j) {
        if (static_cast<int>(j) == k || t > writers[j].time()) continue;
        if ((script.pelvisAt(t) - writers[j].pelvisAt(t)).norm() < options_.min_separation) return false;
      }
    }
    return true;
  }

  // Whether an action of person k written into `trial` may stay: apart from the others and, with
  // close crossings, out of the close zone from `from` to `until` seconds.
  bool fits(const ScriptWriter& trial, int k, const std::vector<ScriptWriter>& writers, double from,
            double until) const {
    return (!options_.close.enabled || keepsClear(trial, from, until)) && keepsApart(trial, k, writers, from, until);
  }

  // Sit down on the own chair (people 1 and 2), stand still, or walk to a point: close in front of
  // the camera (not with close crossings), out of view at the sides, in the middle of the view or
  // anywhere on the free floor.
  void addRandomAction(int k, HashRng* rng, ScriptWriter* writer) const {
    const double r = rng->uniform(0, 1);
    if (canSit(k) && r < options_.sit_probability) {
      sitOnOwnChair(k, rng, writer);
    } else if (r < (canSit(k) ? options_.sit_probability : 0.0) + options_.stand_probability) {
      writer->add(Segment::Kind::kStand, rng->uniform(1.0, 3.5), writer->position(), writer->yaw());
    } else {
      const Eigen::Vector2d target = walkTarget(rng);
      if ((target - writer->position()).norm() > 0.6) writer->walkTo(target);
    }
  }

  void sitOnOwnChair(int k, HashRng* rng, ScriptWriter* writer) const {
    const StaticScene::Seat& seat = scene_.seats()[k];
    const Eigen::Vector2d facing(std::cos(seat.yaw), std::sin(seat.yaw));
    const Eigen::Vector2d approach = seat.position_w.head<2>() + 0.37 * facing;
    writer->walkTo(approach);
    const double turn = wrapAngle(seat.yaw - writer->yaw());
    if (std::abs(turn) > 0.05) {
      writer->add(Segment::Kind::kTurn, std::max(0.3, std::abs(turn) / 2.0), writer->position(), writer->yaw() + turn);
    }
    const Eigen::Vector2d seat_xy = seat.position_w.head<2>();
    writer->add(Segment::Kind::kSitDown, 1.2, seat_xy, writer->yaw())->seat = k;
    writer->add(Segment::Kind::kSit, rng->uniform(3.0, 8.0), seat_xy, writer->yaw())->seat = k;
    writer->add(Segment::Kind::kStandUp, 1.2, approach, writer->yaw())->seat = k;
  }

  Eigen::Vector2d walkTarget(HashRng* rng) const {
    const Eigen::Vector4d& area = area_;
    const double kind = rng->uniform(0, 1);
    // With close crossings, people come close only on them: one at a time.
    const double close = options_.close.enabled ? 0.0 : options_.close_pass_probability;
    const double leave = close + options_.leave_view_probability;
    if (kind < close) {  // close in front of the camera
      return Eigen::Vector2d(rng->uniform(2.3, 3.7), rng->uniform(area[1], area[1] + 0.35));
    }
    if (kind < leave) {  // out of view at the sides
      return Eigen::Vector2d(rng->uniform(0, 1) < 0.5 ? rng->uniform(area[0], area[0] + 0.4)
                                                      : rng->uniform(area[2] - 0.4, area[2]),
                             rng->uniform(area[1], area[1] + 1.0));
    }
    if (kind < leave + options_.middle_probability) {  // across the middle of the view
      return Eigen::Vector2d(rng->uniform(1.8, 4.2), rng->uniform(area[1] + 0.5, area[3]));
    }
    return randomPoint(rng);
  }

  Eigen::Vector2d randomPoint(HashRng* rng) const {
    return Eigen::Vector2d(rng->uniform(area_[0], area_[2]), rng->uniform(area_[1], area_[3]));
  }

  // The crossing that opens the sequence, for the first person not seated at the start, who is
  // moved to its start (so that even a short sequence begins with it).
  PlannedCrossing openingCrossing(std::vector<ScriptWriter>* starts, double earliest, const CrossingShape& shape,
                                  double look) const {
    for (size_t k = 0; k < starts->size(); ++k) {
      ScriptWriter& start = (*starts)[k];
      if (start.time() > 0.0) continue;  // seated
      const PlannedCrossing crossing =
          layOut(static_cast<int>(k), start.position(), start.speed(), earliest, shape, look);
      const Eigen::Vector2d along = crossing.tip - crossing.from;
      start = ScriptWriter(crossing.from, std::atan2(along.y(), along.x()), start.speed());
      return crossing;
    }
    return chooseCrosser(*starts, std::vector<double>(starts->size(), -1e9), earliest, shape, look);
  }

  // The person of `writers` who walks the next crossing, and the crossing fitted to them.
  PlannedCrossing chooseCrosser(const std::vector<ScriptWriter>& writers, const std::vector<double>& last_start,
                                double earliest, const CrossingShape& shape, double look) const {
    std::vector<int> order(writers.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
    std::stable_sort(order.begin(), order.end(), [&last_start](int a, int b) { return last_start[a] < last_start[b]; });
    PlannedCrossing first;
    first.start = 1e18;
    for (const int k : order) {
      const PlannedCrossing crossing = fitCrossing(k, writers[k], earliest, shape, look);
      if (crossing.start <= earliest + 1e-9) return crossing;
      if (crossing.start < first.start) first = crossing;
    }
    return first;
  }

  // The crossing for person k with `shape` whose walk begins at `start` seconds, entered from the
  // side nearer to `position`. Its path is laid out where the camera looks when the person
  // reaches the tip (walking at `speed`, m/s), and moved away from the camera as far as the
  // camera's own motion during the walk would otherwise bring it nearer than min_distance.
  PlannedCrossing layOut(int k, const Eigen::Vector2d& position, double speed, double start,
                         const CrossingShape& shape, double look) const {
    PlannedCrossing crossing;
    crossing.person = k;
    crossing.start = start;
    crossing.look = look;
    double to_tip = (shape.nearest * camera_.half_view_tan + kOutOfViewMargin) / speed;  // seconds, first guess
    double pushed = 0.0;  // metres
    for (int round = 0; round < 4; ++round) {
      CrossingShape moved = shape;
      moved.nearest += pushed;
      const Eigen::Isometry3d T_w_c = camera_.pose_at(start + to_tip);
      const CrossingPath path =
          crossingPathOnFloor(T_w_c, camera_.half_view_tan, moved, options_.close.min_distance + pushed);
      const Eigen::Vector2d to_camera = T_w_c.translation().head<2>() - path.tip;
      crossing.look_heading = std::atan2(to_camera.y(), to_camera.x());
      const bool from_left = (path.left - position).norm() <= (path.right - position).norm();
      crossing.from = from_left ? path.left : path.right;
      crossing.tip = path.tip;
      crossing.to = from_left ? path.right : path.left;
      to_tip = (crossing.tip - crossing.from).norm() / speed;
      pushed += std::max(0.0, options_.close.min_distance + 0.01 - nearestInView(crossing, speed));
    }
    return crossing;
  }

  // The nearest the person of `crossing` comes to the camera centre while in its view (floor
  // distance, metres), walking at `speed` m/s; sampled every 0.1 s.
  double nearestInView(const PlannedCrossing& crossing, double speed) const {
    PlannedCrossing walk_from_zero = crossing;
    walk_from_zero.start = 0.0;
    const Eigen::Vector2d along = crossing.tip - crossing.from;
    ScriptWriter walk(crossing.from, std::atan2(along.y(), along.x()), speed);
    walkCrossing(walk_from_zero, &walk);
    double nearest = 1e9;
    for (double t = 0.0; t <= walk.time(); t += 0.5 * kClearanceStep) {
      const Eigen::Vector2d p = walk.positionAt(t);
      const Eigen::Isometry3d T_w_c = camera_.pose_at(crossing.start + t);
      if (inView(chestInCamera(p, T_w_c))) nearest = std::min(nearest, (p - T_w_c.translation().head<2>()).norm());
    }
    return nearest;
  }

  // The crossing for person k with `shape`, starting at `earliest` or as soon after as the person
  // of `writer` can be at its start. A late start is put 0.3 s after the person could be there:
  // laid out anew for that time, the start moves a little, and the slack keeps the person on time.
  PlannedCrossing fitCrossing(int k, const ScriptWriter& writer, double earliest, const CrossingShape& shape,
                              double look) const {
    PlannedCrossing crossing = layOut(k, writer.position(), writer.speed(), earliest, shape, look);
    for (int round = 0; round < 4; ++round) {
      const double ready = arrival(crossing, writer);
      if (ready <= crossing.start) break;
      crossing = layOut(k, writer.position(), writer.speed(), ready + 0.3, shape, look);
    }
    crossing.start = std::max(crossing.start, arrival(crossing, writer));
    return crossing;
  }

  // Walks to the crossing's start and faces along it.
  static void approach(const PlannedCrossing& crossing, ScriptWriter* writer) {
    writer->walkTo(crossing.from);
    const Eigen::Vector2d along = crossing.tip - crossing.from;
    writer->turnTo(std::atan2(along.y(), along.x()));
  }

  // From the crossing's start (reached by `approach`): waits for its start time, then walks it.
  static void walkCrossing(const PlannedCrossing& crossing, ScriptWriter* writer) {
    approach(crossing, writer);
    writer->standUntil(crossing.start);
    writer->walkTo(crossing.tip);
    if (crossing.look > 0.0) {
      writer->turnTo(crossing.look_heading);
      writer->add(Segment::Kind::kStand, crossing.look, writer->position(), writer->yaw());
    }
    writer->walkTo(crossing.to);
  }

  // When the person of `writer` could be at the crossing's start, facing along it, in seconds.
  static double arrival(const PlannedCrossing& crossing, ScriptWriter writer) {
    approach(crossing, &writer);
    return writer.time();
  }

  const Crowd::Options& options_;
  const StaticScene& scene_;
  const CameraPath& camera_;
  Eigen::Vector4d area_;  // walkable floor (x_min, y_min, x_max, y_max), metres
};

Crowd::Person Crowd::makePerson(const BodyModel& model, const Options& options, HashRng* rng) {
  Person person;
  person.shape = Eigen::VectorXd::Zero(10);
  // Stature (coefficient 0 of the default model) and girth (3) vary most; the shipped model's
  // mean stature is 1.63 m, so coefficient 0 is centred a little above it.
  for (int i = 0; i < 10; ++i) {
    const double spread = (i == 0 || i == 3) ? 0.9 : 0.5;
    person.shape[i] = std::min(2.0, std::max(-2.0, rng->gaussian() * spread + (i == 0 ? 0.3 : 0.0)));
  }
  person.colors = clothe(model, person.shape, rng);
  person.arm_lowering = armLoweringAngle(model, person.shape);
  const auto rest_joints = model.restJoints(person.shape);
  person.rest_pelvis = rest_joints[kPelvis];
  BodyParameters rest;
  rest.shape = person.shape;
  const BodyMesh rest_mesh = model.evaluate(rest);
  float sole = rest_mesh.vertices.empty() ? 0.0f : rest_mesh.vertices[0].y();
  for (const auto& v : rest_mesh.vertices) sole = std::min(sole, v.y());
  person.rest_pelvis_height = person.rest_pelvis.y() - sole;
  person.speed = rng->uniform(options.min_speed, options.max_speed);
  person.stride = 1.0 + 0.35 * person.speed;
  return person;
}

Crowd::Crowd(const Options& options, const StaticScene& scene, std::shared_ptr<const BodyModel> model,
             const CameraPath& camera)
    : options_(options), model_(std::move(model)) {
  if (options.people < 0 || options.people > 5) throw Error("people must be between 0 and 5");
  if (!(options.min_speed > 0.0 && options.max_speed >= options.min_speed)) {
    throw Error("walking speeds must be positive, min_speed <= max_speed");
  }
  if (options.people > 0 && !model_) throw Error("people need a body model");
  if (!(options.min_separation >= 0.0 && options.min_separation <= 2.0)) {
    throw Error("min_separation must lie in 0 .. 2 m");
  }
  checkCloseCrossings(options.close, camera);
  const ScriptPlanner planner(options_, scene, camera);
  // Each person draws from an own stream: shape and clothes, start, actions.
  std::vector<HashRng> rngs;
  for (int k = 0; k < options.people; ++k) {
    rngs.emplace_back(synth::hashOf(options.seed, static_cast<std::uint64_t>(k), 0x9e0931e));
    people_.push_back(makePerson(*model_, options, &rngs[k]));
  }
  std::vector<ScriptWriter> writers;
  if (options.close.enabled) {
    // Crossings are planned from everyone's start.
    for (int k = 0; k < options.people; ++k) writers.push_back(planner.start(k, people_[k].speed, writers, &rngs[k]));
    for (const PlannedCrossing& crossing : planner.planCrossings(&writers)) {
      planner.addCrossing(crossing, &rngs[crossing.person], &writers);
    }
  }
  for (int k = 0; k < options.people; ++k) {
    // Without close crossings a person starts clear of the scripts written before theirs.
    if (!options.close.enabled) writers.push_back(planner.start(k, people_[k].speed, writers, &rngs[k]));
    // The scripts run 2 s past the end, so that the blur's exposure never runs out of script.
    planner.addRandomActionsUntil(options.duration + 2.0, k, &rngs[k], &writers);
  }
  // Released only now: the people written after k keep apart from k's script.
  for (int k = 0; k < options.people; ++k) people_[k].script = writers[k].release();
  seats_ = scene.seats();
}

Crowd::Crowd(const Options& options, const StaticScene& scene, std::shared_ptr<const BodyModel> model)
    : Crowd(options, scene, std::move(model), CameraPath()) {}

Crowd::Posed Crowd::pose(int k, double t) const {
  const Person& person = people_.at(k);
  const auto segmentAt = [&person](double time) -> const Segment& {
    const auto it = std::upper_bound(person.script.begin(), person.script.end(), time,
                                     [](double value, const Segment& s) { return value < s.t1; });
    return it == person.script.end() ? person.script.back() : *it;
  };
  const auto rawAmplitude = [&segmentAt](double time) {
    const Segment& s = segmentAt(time);
    return s.kind == Segment::Kind::kWalk ? 1.0 : s.kind == Segment::Kind::kTurn ? 0.5 : 0.0;
  };
  // Starting and stopping take a moment: the gait amplitude is averaged over +-0.3 s.
  double amplitude = 0.0;
  for (int i = -3; i <= 3; ++i) amplitude += rawAmplitude(t + 0.1 * i) / 7.0;

  const Segment& s = segmentAt(t);
  const double alpha = s.t1 > s.t0 ? std::min(1.0, std::max(0.0, (t - s.t0) / (s.t1 - s.t0))) : 1.0;
  Eigen::Vector2d xy = s.from;
  double yaw = s.yaw0, distance = s.distance0, sit = 0.0;
  switch (s.kind) {
    case Segment::Kind::kWalk:
      xy = s.from + alpha * (s.to - s.from);
      distance += alpha * (s.to - s.from).norm();
      break;
    case Segment::Kind::kTurn:
      yaw = s.yaw0 + smoothstep(alpha) * (s.yaw1 - s.yaw0);
      distance += 0.25 * alpha * std::abs(s.yaw1 - s.yaw0);
      break;
    case Segment::Kind::kStand:
      break;
    case Segment::Kind::kSitDown:
      sit = smoothstep(alpha);
      xy = s.from + sit * (s.to - s.from);
      break;
    case Segment::Kind::kSit:
      sit = 1.0;
      break;
    case Segment::Kind::kStandUp:
      sit = 1.0 - smoothstep(alpha);
      xy = s.from + (1.0 - sit) * (s.to - s.from);
      break;
  }

  JointRotations rotations =
      walkingPose(2.0 * kPi * distance / person.stride, amplitude, person.arm_lowering);
  if (sit > 0.0) {
    const JointRotations seated = sittingPose(person.arm_lowering);
    for (int j = 0; j < kBodyJointCount; ++j) rotations[j] += sit * (seated[j] - rotations[j]);
  }
  // Alive while still: breathing sway standing, a look around sitting.
  rotations[kHead].y() += (0.05 + 0.25 * sit) * std::sin(0.6 * t + k) * (1.0 - amplitude);

  Eigen::Vector3d pelvis_w(xy.x(), xy.y(), person.rest_pelvis_height);
  if (sit > 0.0 && s.seat >= 0) {
    const StaticScene::Seat& seat = seats_[s.seat];
    const Eigen::Vector2d facing(std::cos(seat.yaw), std::sin(seat.yaw));
    const Eigen::Vector2d seat_xy = seat.position_w.head<2>() - 0.05 * facing;
    const Eigen::Vector3d seated(seat_xy.x(), seat_xy.y(), seat.position_w.z() + 0.1);
    const Eigen::Vector3d standing(s.kind == Segment::Kind::kSitDown ? s.from.x() : s.to.x(),
                                   s.kind == Segment::Kind::kSitDown ? s.from.y() : s.to.y(),
                                   person.rest_pelvis_height);
    pelvis_w = standing + sit * (seated - standing);
  }

  Posed posed;
  BodyParameters& p = posed.parameters;
  p.shape = person.shape;
  for (int j = 0; j < kBodyJointCount; ++j) p.pose[j] = rotations[j];
  p.pose[0] = axisAngle(bodyToWorld(yaw) * rotation(rotations[0]));
  p.translation = pelvis_w - person.rest_pelvis;
  posed.mesh = model_->evaluate(p);
  // Feet on the floor (standing and walking): this also gives the gait its vertical bob.
  float lowest = 1e9f;
  for (const auto& v : posed.mesh.vertices) lowest = std::min(lowest, v.z());
  const double lift = -(1.0 - sit) * lowest;
  if (posed.mesh.vertices.empty() || lift == 0.0) return posed;
  for (auto& v : posed.mesh.vertices) v.z() += static_cast<float>(lift);
  for (auto& j : posed.mesh.joints) j.z() += lift;
  p.translation.z() += lift;
  return posed;
}

}  // namespace pf2
