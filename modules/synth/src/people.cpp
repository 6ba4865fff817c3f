#include "pf2/synth/people.h"

#include <algorithm>
#include <cmath>

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

Crowd::Crowd(const Options& options, const StaticScene& scene, std::shared_ptr<const BodyModel> model)
    : options_(options), model_(std::move(model)) {
  if (options.people < 0 || options.people > 5) throw Error("people must be between 0 and 5");
  if (!(options.min_speed > 0.0 && options.max_speed >= options.min_speed)) {
    throw Error("walking speeds must be positive, min_speed <= max_speed");
  }
  if (options.people > 0 && !model_) throw Error("people need a body model");
  const Eigen::Vector4d area = scene.walkableArea();
  const auto randomPoint = [&area](HashRng* rng) {
    return Eigen::Vector2d(rng->uniform(area[0], area[2]), rng->uniform(area[1], area[3]));
  };
  for (int k = 0; k < options.people; ++k) {
    HashRng rng(synth::hashOf(options.seed, static_cast<std::uint64_t>(k), 0x9e0931e));
    Person person;
    person.shape = Eigen::VectorXd::Zero(10);
    // Stature (coefficient 0 of the default model) and girth (3) vary most; the shipped model's
    // mean stature is 1.63 m, so coefficient 0 is centred a little above it.
    for (int i = 0; i < 10; ++i) {
      const double spread = (i == 0 || i == 3) ? 0.9 : 0.5;
      person.shape[i] = std::min(2.0, std::max(-2.0, rng.gaussian() * spread + (i == 0 ? 0.3 : 0.0)));
    }
    person.colors = clothe(*model_, person.shape, &rng);
    person.arm_lowering = armLoweringAngle(*model_, person.shape);
    const auto rest_joints = model_->restJoints(person.shape);
    person.rest_pelvis = rest_joints[kPelvis];
    BodyParameters rest;
    rest.shape = person.shape;
    const BodyMesh rest_mesh = model_->evaluate(rest);
    float sole = rest_mesh.vertices.empty() ? 0.0f : rest_mesh.vertices[0].y();
    for (const auto& v : rest_mesh.vertices) sole = std::min(sole, v.y());
    person.rest_pelvis_height = person.rest_pelvis.y() - sole;
    const double speed = rng.uniform(options.min_speed, options.max_speed);  // m/s
    person.stride = 1.0 + 0.35 * speed;

    // The script: from a random start, walk to points near the camera, out of view or anywhere
    // on the free floor, stop now and then, and (the first two people) sit on their chair.
    Eigen::Vector2d position = randomPoint(&rng);
    double yaw = rng.uniform(-kPi, kPi), distance = 0.0, t = 0.0;
    const bool can_sit = k < static_cast<int>(scene.seats().size());
    auto add = [&](Segment::Kind kind, double duration, const Eigen::Vector2d& to, double yaw1) {
      Segment s;
      s.kind = kind;
      s.t0 = t;
      s.t1 = t + duration;
      s.from = position;
      s.to = to;
      s.yaw0 = yaw;
      s.yaw1 = yaw1;
      s.distance0 = distance;
      if (kind == Segment::Kind::kWalk) distance += (to - position).norm();
      if (kind == Segment::Kind::kTurn) distance += 0.25 * std::abs(wrapAngle(yaw1 - yaw));
      person.script.push_back(s);
      t += duration;
      if (kind != Segment::Kind::kSitDown && kind != Segment::Kind::kSit) position = to;
      yaw = yaw1;
      return &person.script.back();
    };
    auto walkTo = [&](const Eigen::Vector2d& target) {
      const Eigen::Vector2d d = target - position;
      if (d.norm() < 0.05) return;
      const double heading = std::atan2(d.y(), d.x());
      const double turn = std::abs(wrapAngle(heading - yaw));
      if (turn > 0.05) add(Segment::Kind::kTurn, std::max(0.3, turn / 2.5), position, yaw + wrapAngle(heading - yaw));
      add(Segment::Kind::kWalk, d.norm() / speed, target, yaw);
    };
    if (k == 0 && can_sit && options.first_person_seated) {
      // As in TUM fr3/walking_*, someone sits at the desk when the recording starts.
      const StaticScene::Seat& seat = scene.seats()[0];
      position = seat.position_w.head<2>() + 0.37 * Eigen::Vector2d(std::cos(seat.yaw), std::sin(seat.yaw));
      yaw = seat.yaw;
      add(Segment::Kind::kSit, rng.uniform(2.0, 5.0), seat.position_w.head<2>(), yaw)->seat = 0;
      add(Segment::Kind::kStandUp, 1.2, position, yaw)->seat = 0;
    }
    while (t < options.duration + 2.0) {
      const double r = rng.uniform(0, 1);
      if (can_sit && r < options.sit_probability) {
        const StaticScene::Seat& seat = scene.seats()[k];
        const Eigen::Vector2d facing(std::cos(seat.yaw), std::sin(seat.yaw));
        const Eigen::Vector2d approach = seat.position_w.head<2>() + 0.37 * facing;
        walkTo(approach);
        const double turn = wrapAngle(seat.yaw - yaw);
        if (std::abs(turn) > 0.05) add(Segment::Kind::kTurn, std::max(0.3, std::abs(turn) / 2.0), position, yaw + turn);
        const Eigen::Vector2d seat_xy = seat.position_w.head<2>();
        add(Segment::Kind::kSitDown, 1.2, seat_xy, yaw)->seat = k;
        add(Segment::Kind::kSit, rng.uniform(3.0, 8.0), seat_xy, yaw)->seat = k;
        add(Segment::Kind::kStandUp, 1.2, approach, yaw)->seat = k;
      } else if (r < (can_sit ? options.sit_probability : 0.0) + options.stand_probability) {
        add(Segment::Kind::kStand, rng.uniform(1.0, 3.5), position, yaw);
      } else {
        const double kind = rng.uniform(0, 1);
        Eigen::Vector2d target;
        const double close = options.close_pass_probability;
        const double leave = close + options.leave_view_probability;
        if (kind < close) {  // close in front of the camera
          target = Eigen::Vector2d(rng.uniform(2.3, 3.7), rng.uniform(area[1], area[1] + 0.35));
        } else if (kind < leave) {  // out of view at the sides
          target = Eigen::Vector2d(rng.uniform(0, 1) < 0.5 ? rng.uniform(area[0], area[0] + 0.4)
                                                            : rng.uniform(area[2] - 0.4, area[2]),
                                   rng.uniform(area[1], area[1] + 1.0));
        } else if (kind < leave + options.middle_probability) {  // across the middle of the view
          target = Eigen::Vector2d(rng.uniform(1.8, 4.2), rng.uniform(area[1] + 0.5, area[3]));
        } else {
          target = randomPoint(&rng);
        }
        if ((target - position).norm() > 0.6) walkTo(target);
      }
    }
    people_.push_back(std::move(person));
  }
  seats_ = scene.seats();
}

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
