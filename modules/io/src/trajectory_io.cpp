#include "pf2/io/trajectory_io.h"

#include <algorithm>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"
#include "pf2/core/text_lines.h"

namespace pf2 {

Trajectory readTrajectory(const std::string& path) {
  Trajectory trajectory;
  forEachDataLine(path, "trajectory file", [&](const std::string& line, int line_number) {
    StampedPose pose;
    if (!parseTumLine(line, &pose)) {
      throw fileError(path, line_number,
                      "expected 'timestamp tx ty tz qx qy qz qw' with finite numbers and a "
                      "non-zero quaternion, got '" + line + "'");
    }
    trajectory.push_back(pose);
  });
  std::stable_sort(trajectory.begin(), trajectory.end(),
                   [](const StampedPose& a, const StampedPose& b) { return a.timestamp < b.timestamp; });
  return trajectory;
}

void writeTrajectory(const std::string& path, const Trajectory& trajectory) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "# timestamp tx ty tz qx qy qz qw (T_w_c, metres)\n";
    for (const StampedPose& pose : trajectory) out << toTumLine(pose) << "\n";
  });
}

}  // namespace pf2
