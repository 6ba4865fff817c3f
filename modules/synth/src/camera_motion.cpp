#include "pf2/synth/camera_motion.h"

#include <algorithm>
#include <cmath>

#include "pf2/core/error.h"

namespace pf2 {

namespace {
constexpr double kPi = 3.14159265358979323846;
const Eigen::Vector3d kHome(3.0, 0.7, 1.45);    // default camera position, metres
const Eigen::Vector3d kTarget(3.0, 3.8, 0.85);  // the desk, where it looks

// One smooth excursion 0 -> +A -> -A -> 0 over s in [0, 1], at rest at both ends.
double excursion(double s) { return std::sin(2.0 * kPi * s) * std::sin(kPi * s) / 0.77; }
}  // namespace

CameraMotion cameraMotionFromName(const std::string& name) {
  if (name == "static") return CameraMotion::kStatic;
  if (name == "xyz") return CameraMotion::kXyz;
  if (name == "halfsphere") return CameraMotion::kHalfsphere;
  if (name == "rpy") return CameraMotion::kRpy;
  if (name == "loop") return CameraMotion::kLoop;
  if (name == "above") return CameraMotion::kAbove;
  throw Error("unknown camera motion '" + name + "' (expected static, xyz, halfsphere, rpy, loop or above)");
}

const char* cameraMotionName(CameraMotion motion) {
  switch (motion) {
    case CameraMotion::kStatic: return "static";
    case CameraMotion::kXyz: return "xyz";
    case CameraMotion::kHalfsphere: return "halfsphere";
    case CameraMotion::kRpy: return "rpy";
    case CameraMotion::kLoop: return "loop";
    case CameraMotion::kAbove: return "above";
  }
  return "?";
}

Eigen::Isometry3d lookAt(const Eigen::Vector3d& position_w, const Eigen::Vector3d& target_w) {
  const Eigen::Vector3d forward = (target_w - position_w).normalized();
  const Eigen::Vector3d right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d down = forward.cross(right);
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  T_w_c.linear().col(0) = right;
  T_w_c.linear().col(1) = down;
  T_w_c.linear().col(2) = forward;
  T_w_c.translation() = position_w;
  return T_w_c;
}

Eigen::Isometry3d cameraPoseAt(CameraMotion motion, double t, double duration) {
  const Eigen::Isometry3d home = lookAt(kHome, kTarget);
  switch (motion) {
    case CameraMotion::kStatic: {
      // A hand-held-steady camera on a tripod still shakes by a few millimetres.
      Eigen::Isometry3d T = home;
      T.translation() += home.linear() * Eigen::Vector3d(0.002 * std::sin(1.3 * t),
                                                         0.0015 * std::sin(0.9 * t + 1.0),
                                                         0.002 * std::sin(0.7 * t + 2.0));
      T.linear() = T.linear() * Eigen::AngleAxisd(0.003 * std::sin(0.8 * t), Eigen::Vector3d::UnitY()).toRotationMatrix();
      return T;
    }
    case CameraMotion::kXyz: {
      const double segment = 4.0;  // seconds per axis
      const int axis = static_cast<int>(std::floor(t / segment)) % 3;
      const double s = t / segment - std::floor(t / segment);
      Eigen::Vector3d offset_c = Eigen::Vector3d::Zero();
      offset_c[axis] = 0.25 * excursion(s);
      Eigen::Isometry3d T = home;
      T.translation() += home.linear() * offset_c;
      return T;
    }
    case CameraMotion::kHalfsphere: {
      const Eigen::Vector3d centre(3.0, 1.2, 1.3);
      const double azimuth = 0.9 * std::sin(2.0 * kPi * t / 9.0);
      const double elevation = 0.5 * std::sin(2.0 * kPi * t / 5.3 + 0.4);
      const Eigen::Vector3d position =
          centre + 0.5 * Eigen::Vector3d(std::sin(azimuth) * std::cos(elevation),
                                         -std::cos(azimuth) * std::cos(elevation), std::sin(elevation));
      return lookAt(position, kTarget);
    }
    case CameraMotion::kRpy: {
      const double segment = 4.0;
      const int axis = static_cast<int>(std::floor(t / segment)) % 3;
      const double s = t / segment - std::floor(t / segment);
      // Roll about the optical axis first, then pitch (x), then yaw (y), as the TUM rpy sequences.
      const int camera_axis = axis == 0 ? 2 : axis == 1 ? 0 : 1;
      const double angle = 20.0 * kPi / 180.0 * excursion(s);
      Eigen::Isometry3d T = home;
      T.linear() = home.linear() * Eigen::AngleAxisd(angle, Eigen::Vector3d::Unit(camera_axis)).toRotationMatrix();
      return T;
    }
    case CameraMotion::kLoop: {
      const double period = std::max(duration, 10.0);
      const double theta = 2.0 * kPi * t / period - kPi / 2.0;  // starts at the ellipse's front
      const Eigen::Vector3d position(3.0 + 1.5 * std::cos(theta), 1.0 + 0.3 * std::sin(theta),
                                     1.45 + 0.02 * std::sin(4.0 * theta + kPi / 2.0) - 0.02);
      const Eigen::Vector3d target(3.0 + 1.3 * std::sin(2.0 * kPi * t / period), 3.8,
                                   0.85 + 0.15 * std::sin(4.0 * kPi * t / period));
      return lookAt(position, target);
    }
    case CameraMotion::kAbove: {
      // 2 m above the floor point it looks at, 2.1 m back from it: 38-45 degrees down, so people's
      // heads and shoulders face the camera rather than their fronts. Slow pan (±0.9 m at the
      // floor) and drift (±0.4 m sideways, ±0.1 m back and forth), as a robot's mast camera.
      const Eigen::Vector3d position(3.0 + 0.4 * std::sin(2.0 * kPi * t / 12.0),
                                     0.5 + 0.1 * std::sin(2.0 * kPi * t / 8.0), 2.4);
      const Eigen::Vector3d target(3.0 + 0.9 * std::sin(2.0 * kPi * t / 9.0 + 0.5), 2.6, 0.4);
      return lookAt(position, target);
    }
  }
  return home;
}

}  // namespace pf2
