#pragma once
// Pose helpers. Poses are T_w_c: camera to world, as in TUM trajectory files.
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace pf2 {

struct StampedPose {
  double timestamp = 0.0;
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
};
using Trajectory = std::vector<StampedPose>;

// "timestamp tx ty tz qx qy qz qw" with full precision (the TUM trajectory line).
std::string toTumLine(const StampedPose& pose);
// Parses the first eight numbers of a TUM line (extra columns are ignored). The quaternion is
// normalised; returns false on fewer than eight numbers, non-finite values or a zero quaternion.
bool parseTumLine(const std::string& line, StampedPose* pose);

// Pose between a and b: translation linear, rotation slerp; alpha in [0, 1].
Eigen::Isometry3d interpolate(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double alpha);
// Pose at time t from a trajectory sorted by time. Returns false when t lies outside its span or
// the neighbours are farther apart than max_gap seconds (no extrapolation, no bridging of gaps).
bool interpolateAt(const Trajectory& trajectory, double t, double max_gap, Eigen::Isometry3d* T_w_c);

// Rotation angle (radians) of a rotation matrix, robust near 0 and pi.
double rotationAngle(const Eigen::Matrix3d& R);

}  // namespace pf2
