#pragma once
// Internal: calls handle(line, number) for each data line of a text file: CRLF tolerated, blank
// lines and '#' comments skipped. Throws pf2::Error naming the file when it cannot be opened.
#include <fstream>
#include <string>

#include "pf2/core/error.h"

namespace pf2 {

template <typename Handle>
void forEachDataLine(const std::string& path, const std::string& what, Handle handle) {
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
