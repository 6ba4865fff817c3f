#pragma once
// The TUM RGB-D benchmark's text lists (rgb.txt, depth.txt, associations) and timestamp association.
#include <string>
#include <utility>
#include <vector>

namespace pf2 {

// One line of rgb.txt / depth.txt: "timestamp filename [ignored columns]".
struct TumListEntry {
  double timestamp = 0.0;
  std::string file;  // as written in the list, relative to the sequence folder
  int line = 0;      // line number in the list, for error messages
};

// Reads a TUM file list. '#' comment lines, blank lines, CRLF endings and extra columns are
// tolerated; a line without a finite timestamp and a file name throws pf2::Error "path:line: ...".
std::vector<TumListEntry> readTumList(const std::string& path);

// Matches two timestamp lists the way the TUM benchmark's associate.py does: every pair closer than
// max_difference seconds is a candidate, candidates are taken greedily from the closest, and no
// stamp is used twice. Returns (index into a, index into b) pairs sorted by a's index.
std::vector<std::pair<size_t, size_t>> associateTimestamps(const std::vector<double>& a,
                                                           const std::vector<double>& b,
                                                           double max_difference);

// One line of an associations file: "rgb_stamp rgb_file depth_stamp depth_file".
struct TumAssociation {
  TumListEntry rgb;
  TumListEntry depth;
};
std::vector<TumAssociation> readTumAssociations(const std::string& path);

}  // namespace pf2
