#include "pf2/io/tum_lists.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "pf2/core/error.h"
#include "pf2/core/text_lines.h"

namespace pf2 {

namespace {

bool readEntry(std::istringstream& fields, int line_number, TumListEntry* entry) {
  entry->line = line_number;
  return static_cast<bool>(fields >> entry->timestamp >> entry->file) &&
         std::isfinite(entry->timestamp);
}

// A recording's stamps increase line by line; a repeated or earlier one is a broken list (it would
// silently drop or reorder frames).
void requireIncreasing(const std::string& path, const TumListEntry& previous, const TumListEntry& entry) {
  if (entry.timestamp > previous.timestamp) return;
  char text[160];
  std::snprintf(text, sizeof(text), "timestamp %.6f is not after the one on line %d (%.6f): stamps must increase",
                entry.timestamp, previous.line, previous.timestamp);
  throw fileError(path, entry.line, text);
}

}  // namespace

std::vector<TumListEntry> readTumList(const std::string& path) {
  std::vector<TumListEntry> entries;
  forEachDataLine(path, "file list", [&](const std::string& line, int number) {
    std::istringstream fields(line);
    TumListEntry entry;
    if (!readEntry(fields, number, &entry)) {
      throw fileError(path, number, "expected 'timestamp filename', got '" + line + "'");
    }
    if (!entries.empty()) requireIncreasing(path, entries.back(), entry);
    entries.push_back(entry);
  });
  return entries;
}

std::vector<TumAssociation> readTumAssociations(const std::string& path) {
  std::vector<TumAssociation> pairs;
  forEachDataLine(path, "associations file", [&](const std::string& line, int number) {
    std::istringstream fields(line);
    TumAssociation pair;
    if (!readEntry(fields, number, &pair.rgb) || !readEntry(fields, number, &pair.depth)) {
      throw fileError(path, number,
                      "expected 'rgb_stamp rgb_file depth_stamp depth_file', got '" + line + "'");
    }
    if (!pairs.empty()) requireIncreasing(path, pairs.back().rgb, pair.rgb);
    pairs.push_back(pair);
  });
  return pairs;
}

std::vector<std::pair<size_t, size_t>> associateTimestamps(const std::vector<double>& a,
                                                           const std::vector<double>& b,
                                                           double max_difference) {
  // Candidates within the window, found on sorted copies so this stays O(n log n + candidates).
  std::vector<size_t> order_b(b.size());
  for (size_t j = 0; j < b.size(); ++j) order_b[j] = j;
  std::sort(order_b.begin(), order_b.end(), [&](size_t x, size_t y) { return b[x] < b[y]; });

  struct Candidate {
    double difference;
    size_t i, j;
  };
  std::vector<Candidate> candidates;
  for (size_t i = 0; i < a.size(); ++i) {
    auto it = std::lower_bound(order_b.begin(), order_b.end(), a[i] - max_difference,
                               [&](size_t j, double value) { return b[j] < value; });
    for (; it != order_b.end() && b[*it] < a[i] + max_difference; ++it) {
      const double difference = std::abs(a[i] - b[*it]);
      if (difference < max_difference) candidates.push_back({difference, i, *it});
    }
  }
  // Closest first; ties broken by index so the result does not depend on sort stability.
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& x, const Candidate& y) {
    if (x.difference != y.difference) return x.difference < y.difference;
    if (x.i != y.i) return x.i < y.i;
    return x.j < y.j;
  });
  std::vector<bool> used_a(a.size(), false), used_b(b.size(), false);
  std::vector<std::pair<size_t, size_t>> matches;
  for (const Candidate& c : candidates) {
    if (used_a[c.i] || used_b[c.j]) continue;
    used_a[c.i] = used_b[c.j] = true;
    matches.emplace_back(c.i, c.j);
  }
  std::sort(matches.begin(), matches.end());
  return matches;
}

}  // namespace pf2
