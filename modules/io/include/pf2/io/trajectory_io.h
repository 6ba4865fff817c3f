#pragma once
// TUM trajectory files: "timestamp tx ty tz qx qy qz qw" (T_w_c), '#' comments.
#include <string>

#include "pf2/core/pose.h"

namespace pf2 {

// Reads groundtruth.txt or an estimate. Comments, blank lines, CRLF and extra columns are
// tolerated; a malformed line throws pf2::Error "path:line: ...". The result is sorted by time;
// an empty file yields an empty trajectory (callers decide whether that is an error).
Trajectory readTrajectory(const std::string& path);

// Writes atomically (temporary file + rename) with a header comment.
void writeTrajectory(const std::string& path, const Trajectory& trajectory);

// What the poses of a ground-truth file are. Both are TUM-format lines; they differ in meaning.
enum class TrajectoryFormat {
  kTum,   // camera poses T_w_c (TUM RGB-D benchmark, our own outputs)
  kBonn,  // Bonn RGB-D Dynamic Dataset groundtruth.txt as published: motion-capture marker poses
};

// "tum" | "bonn". `option` says where the name came from (e.g. "--gt-format"); an unknown name
// throws pf2::Error "<option>: unknown trajectory format 'x' (allowed: tum, bonn)".
TrajectoryFormat parseTrajectoryFormat(const std::string& name, const std::string& option);

// readTrajectory, then, for kBonn, convertBonnMarkerToCamera: camera poses either way.
Trajectory readTrajectory(const std::string& path, TrajectoryFormat format);

// The Bonn dataset's rule for camera poses from its marker poses:
//   T_w_c = T_ros * T_gt * T_ros * T_m
// with T_ros the axis swap [[-1,0,0],[0,0,1],[0,1,0]] (its own inverse) and T_m =
// bonnMarkerToCamera(). Timestamps are kept.
Trajectory convertBonnMarkerToCamera(const Trajectory& marker_poses);

// T_m of the rule above: the dataset's published "marker to camera" transform, rotation made
// orthonormal. It maps camera-frame points into the (axis-swapped) marker frame.
Eigen::Isometry3d bonnMarkerToCamera();

}  // namespace pf2
