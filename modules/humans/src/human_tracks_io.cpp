#include "pf2/humans/human_track.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <vector>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"
#include "pf2/core/text_lines.h"

namespace pf2 {

std::array<double, 3> personColour(int id) {
  static const std::array<std::array<double, 3>, 8> kPalette = {{{1.0, 0.35, 0.2},
                                                                  {0.25, 0.45, 1.0},
                                                                  {1.0, 0.85, 0.1},
                                                                  {0.8, 0.3, 1.0},
                                                                  {0.1, 0.9, 0.8},
                                                                  {1.0, 0.4, 0.7},
                                                                  {0.6, 1.0, 0.3},
                                                                  {1.0, 0.6, 0.1}}};
  return kPalette[static_cast<std::size_t>(std::max(id, 0)) % kPalette.size()];
}

void writeHumanTracks(const std::string& path, const std::vector<HumanTrack>& tracks) {
  struct Line {
    double timestamp;
    int id;
    const Eigen::Vector3d* p_w;
  };
  std::vector<Line> lines;
  for (const HumanTrack& track : tracks) {
    for (const HumanTrackPoint& point : track.points) lines.push_back({point.timestamp, track.id, &point.p_w});
  }
  std::stable_sort(lines.begin(), lines.end(), [](const Line& a, const Line& b) {
    return a.timestamp != b.timestamp ? a.timestamp < b.timestamp : a.id < b.id;
  });
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "# timestamp id x y z (person centre, world frame, metres)\n";
    char buffer[160];
    for (const Line& line : lines) {
      std::snprintf(buffer, sizeof(buffer), "%.6f %d %.6f %.6f %.6f\n", line.timestamp, line.id,
                    line.p_w->x(), line.p_w->y(), line.p_w->z());
      out << buffer;
    }
  });
}

std::vector<HumanTrack> readHumanTracks(const std::string& path) {
  std::map<int, HumanTrack> by_id;
  std::map<std::pair<double, int>, std::vector<int>> lines;  // (timestamp, id) -> line numbers
  forEachDataLine(path, "human trajectory file", [&](const std::string& line, int number) {
    std::istringstream fields(line);
    double timestamp = 0, x = 0, y = 0, z = 0;
    long id = -1;
    if (!(fields >> timestamp >> id >> x >> y >> z) || id < 0 || id > 1000000 ||
        !std::isfinite(timestamp) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z)) {
      throw fileError(path, number, "expected 'timestamp id x y z' with finite numbers and an id >= 0, got '" +
                                        line + "'");
    }
    HumanTrack& track = by_id[static_cast<int>(id)];
    track.id = static_cast<int>(id);
    track.points.push_back({timestamp, Eigen::Vector3d(x, y, z)});
    lines[{timestamp, static_cast<int>(id)}].push_back(number);
  });
  // One position per person and frame: a repeated (timestamp, id) is a broken file.
  for (const auto& [key, numbers] : lines) {
    if (numbers.size() > 1) {
      throw fileError(path, numbers[1], "person " + std::to_string(key.second) + " already has a position at this "
                                        "timestamp (line " + std::to_string(numbers[0]) + ")");
    }
  }
  std::vector<HumanTrack> tracks;
  for (auto& [id, track] : by_id) {
    std::stable_sort(track.points.begin(), track.points.end(),
                     [](const HumanTrackPoint& a, const HumanTrackPoint& b) { return a.timestamp < b.timestamp; });
    tracks.push_back(std::move(track));
  }
  return tracks;
}

}  // namespace pf2
