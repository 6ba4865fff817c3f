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

}  // namespace pf2
