#pragma once
// A person's trajectory (data object) and its file: `timestamp id x y z` lines, world frame,
// metres, '#' comments (DESIGN.md). The same format holds pf2_synth's ground truth gt/people.txt.
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace pf2 {

struct HumanTrackPoint {
  double timestamp = 0.0;                   // seconds
  Eigen::Vector3d p_w = Eigen::Vector3d::Zero();  // the person's centre, world frame, metres
};

struct HumanTrack {
  int id = 0;                               // stable small integer, 1, 2, ... in order of appearance
  std::vector<HumanTrackPoint> points;      // sorted by time, at most one per frame
};

// The colour of person `id` everywhere (scene files, pf2_view): distinct, bright colours that
// read on a dark background, 8 of them in turn; RGB in [0, 1]. Thread safe.
std::array<double, 3> personColour(int id);

// Writes all points, sorted by time then id, with 6 decimals (microseconds, micrometres) and a
// header comment, atomically (temporary file + rename). Throws pf2::Error naming the path on
// failure. Thread safe (for different paths).
void writeHumanTracks(const std::string& path, const std::vector<HumanTrack>& tracks);

// Reads a `timestamp id x y z` file (extra columns ignored; CRLF, blank and '#' lines tolerated).
// Returns the tracks sorted by id, each track's points sorted by time. A malformed line (missing
// or non-finite numbers, an id outside 0..10^6) throws pf2::Error "path:line: ..."; a missing
// file throws "path: cannot open ...". Thread safe.
std::vector<HumanTrack> readHumanTracks(const std::string& path);

}  // namespace pf2
