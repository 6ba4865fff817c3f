#pragma once
// Internal: the entry of a timestamp-keyed map nearest to t, within max_difference seconds.
#include <cmath>
#include <iterator>
#include <map>

namespace pf2 {

template <typename Value>
const Value* nearestStamp(const std::map<double, Value>& entries, double t, double max_difference) {
  if (entries.empty()) return nullptr;
  auto after = entries.lower_bound(t);
  auto best = entries.end();
  if (after != entries.end()) best = after;
  if (after != entries.begin()) {
    auto before = std::prev(after);
    if (best == entries.end() || t - before->first < best->first - t) best = before;
  }
  if (std::abs(best->first - t) > max_difference) return nullptr;
  return &best->second;
}

}  // namespace pf2
