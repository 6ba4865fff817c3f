#include "pf2/core/pose.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace pf2 {

std::string toTumLine(const StampedPose& pose) {
  const Eigen::Vector3d t = pose.T_w_c.translation();
  const Eigen::Quaterniond q(pose.T_w_c.rotation());
  char buffer[256];
  std::snprintf(buffer, sizeof(buffer), "%.6f %.9g %.9g %.9g %.9g %.9g %.9g %.9g", pose.timestamp,
                t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  return buffer;
}

bool parseTumLine(const std::string& line, StampedPose* pose) {
  std::istringstream in(line);
  double v[8];
  for (double& x : v) {
    if (!(in >> x) || !std::isfinite(x)) return false;
  }
  Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
  // A quaternion so large its norm overflows would normalise to nonsense: refused like a zero one.
  const double norm = q.norm();
  if (!(norm > 1e-9) || !std::isfinite(norm)) return false;
  q.coeffs() /= norm;
  pose->timestamp = v[0];
  pose->T_w_c = Eigen::Isometry3d::Identity();
  pose->T_w_c.linear() = q.toRotationMatrix();
  pose->T_w_c.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
  return true;
}

Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b,
                              double alpha) {
  const Eigen::Quaterniond qa(a.rotation());
  const Eigen::Quaterniond qb(b.rotation());
  Eigen::Isometry3d result = Eigen::Isometry3d::Identity();
  result.linear() = qa.slerp(alpha, qb).toRotationMatrix();
  result.translation() = (1.0 - alpha) * a.translation() + alpha * b.translation();
  return result;
}

bool interpolateAt(const Trajectory& trajectory, double t, double max_gap,
                   Eigen::Isometry3d* T_w_c) {
  if (trajectory.empty()) return false;
  const auto after = std::lower_bound(
      trajectory.begin(), trajectory.end(), t,
      [](const StampedPose& p, double time) { return p.timestamp < time; });
  if (after == trajectory.end()) return false;
  if (after->timestamp == t) {
    *T_w_c = after->T_w_c;
    return true;
  }
  if (after == trajectory.begin()) return false;
  const auto before = after - 1;
  const double gap = after->timestamp - before->timestamp;
  if (gap > max_gap || gap <= 0.0) return false;
  *T_w_c = interpolate(before->T_w_c, after->T_w_c, (t - before->timestamp) / gap);
  return true;
}

double rotationAngle(const Eigen::Matrix3d& R) {
  // atan2 of (|axis| * sin, cos) stays accurate at both small and near-pi angles.
  const Eigen::Vector3d axis_sin(R(2, 1) - R(1, 2), R(0, 2) - R(2, 0), R(1, 0) - R(0, 1));
  const double cos_angle = 0.5 * (R.trace() - 1.0);
  return std::atan2(0.5 * axis_sin.norm(), cos_angle);
}

}  // namespace pf2
