#include "pf2/io/trajectory_io.h"

#include <algorithm>
#include <fstream>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"

namespace pf2 {

Trajectory readTrajectory(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open trajectory file");
  Trajectory trajectory;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    StampedPose pose;
    if (!parseTumLine(line, &pose)) {
      throw fileError(path, line_number,
                      "expected 'timestamp tx ty tz qx qy qz qw' with finite numbers and a "
                      "non-zero quaternion, got '" + line + "'");
    }
    trajectory.push_back(pose);
  }
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
