#include "pf2/io/trajectory_io.h"

#include <algorithm>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"
#include "pf2/core/text_lines.h"

namespace pf2 {

Trajectory readTrajectory(const std::string& path) {
  Trajectory trajectory;
  std::vector<int> lines;
  forEachDataLine(path, "trajectory file", [&](const std::string& line, int line_number) {
    StampedPose pose;
    if (!parseTumLine(line, &pose)) {
      throw fileError(path, line_number,
                      "expected 'timestamp tx ty tz qx qy qz qw' with finite numbers and a quaternion "
                      "of finite, non-zero norm, got '" + line + "'");
    }
    trajectory.push_back(pose);
    lines.push_back(line_number);
  });
  // Sorted by time (files may list poses in any order); two poses of one stamp are a broken file.
  std::vector<size_t> order(trajectory.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return trajectory[a].timestamp < trajectory[b].timestamp; });
  Trajectory sorted;
  for (size_t k = 0; k < order.size(); ++k) {
    if (k > 0 && trajectory[order[k]].timestamp == trajectory[order[k - 1]].timestamp) {
      throw fileError(path, lines[order[k]],
                      "timestamp already given on line " + std::to_string(lines[order[k - 1]]) +
                          " (one pose per timestamp)");
    }
    sorted.push_back(trajectory[order[k]]);
  }
  return sorted;
}

void writeTrajectory(const std::string& path, const Trajectory& trajectory) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "# timestamp tx ty tz qx qy qz qw (T_w_c, metres)\n";
    for (const StampedPose& pose : trajectory) out << toTumLine(pose) << "\n";
  });
}

TrajectoryFormat parseTrajectoryFormat(const std::string& name, const std::string& option) {
  if (name == "tum") return TrajectoryFormat::kTum;
  if (name == "bonn") return TrajectoryFormat::kBonn;
  throw Error(option + ": unknown trajectory format '" + name + "' (allowed: tum, bonn)");
}

Trajectory readTrajectory(const std::string& path, TrajectoryFormat format) {
  Trajectory trajectory = readTrajectory(path);
  if (format == TrajectoryFormat::kBonn) trajectory = convertBonnMarkerToCamera(trajectory);
  return trajectory;
}

Eigen::Isometry3d bonnMarkerToCamera() {
  // The dataset publishes T_m to four digits with a rotation part that is not orthonormal
  // (scale ~1.059): [[1.0157 0.1828 -0.2389 0.0113] [0.0009 -0.8431 -0.6413 -0.0098]
  // [-0.3009 0.6147 -0.8085 0.0111]]. The values below are recovered from the dataset itself:
  // T_m = (T_ros T_gt T_ros)^-1 T_cam on each of the 153 poses of bonn_crowd_250_150 (marker
  // poses gt/groundtruth_marker.txt, converted camera poses groundtruth.txt), which agree to
  // 1.3e-6 (the 6-decimal rounding of the converted file); mean, then the nearest rotation by SVD.
  // That rotation is the SVD polar factor of the published matrix to 5e-8, and the translation
  // is the published one.
  Eigen::Matrix3d R_m;
  R_m << 0.9588191449, 0.1725935764, -0.2255599802,
         0.0008446003, -0.7959059898, -0.6054196413,
         -0.2840160804, 0.5802974348, -0.7632756732;
  Eigen::Isometry3d T_m = Eigen::Isometry3d::Identity();
  // Through a unit quaternion, so the 10-digit rounding above leaves no non-orthonormal residue.
  T_m.linear() = Eigen::Quaterniond(R_m).normalized().toRotationMatrix();
  T_m.translation() = Eigen::Vector3d(0.0113, -0.0098, 0.0111);
  return T_m;
}

Trajectory convertBonnMarkerToCamera(const Trajectory& marker_poses) {
  // The dataset's rule as published: T_ros re-expresses the motion-capture axes (on the world
  // side and on the marker side) before T_m moves from the marker to the camera.
  Eigen::Isometry3d T_ros = Eigen::Isometry3d::Identity();
  T_ros.linear() << -1, 0, 0,
                     0, 0, 1,
                     0, 1, 0;
  const Eigen::Isometry3d T_m = bonnMarkerToCamera();
  Trajectory camera_poses = marker_poses;
  for (StampedPose& pose : camera_poses) pose.T_w_c = T_ros * pose.T_w_c * T_ros * T_m;
  return camera_poses;
}

}  // namespace pf2
