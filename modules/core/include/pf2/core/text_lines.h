#pragma once
// Calls handle(line, number) for each data line of a text file: CRLF tolerated, blank lines and
// lines starting with '#' skipped (a '#' later in a line is left to the handler). Throws pf2::Error
// "path: cannot open <what>" when the file cannot be opened or is a folder. Every reader of our text formats
// (TUM lists and trajectories, calibration, config, boxes) goes through it.
#include <filesystem>
#include <fstream>
#include <string>

#include "pf2/core/error.h"

namespace pf2 {

template <typename Handle>
void forEachDataLine(const std::string& path, const std::string& what, Handle handle) {
  std::error_code ignored;
  // A folder opens as an empty stream on Linux: it would read as a file without lines.
  if (std::filesystem::is_directory(path, ignored)) throw fileError(path, "is a folder, not a " + what);
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open " + what);
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    handle(line, number);
  }
}

}  // namespace pf2
