#pragma once
// The median every stage takes of a few hundred to a few hundred thousand values (depths,
// offsets, errors): the element at index size / 2 once sorted (the upper of the two middle ones
// for an even count), found by a partial sort. Reorders *values. Header-only.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace pf2 {

// `empty` when *values holds nothing.
template <typename T>
T upperMedian(std::vector<T>* values, T empty = T(0)) {
  if (values->empty()) return empty;
  const auto middle = values->begin() + static_cast<std::ptrdiff_t>(values->size() / 2);
  std::nth_element(values->begin(), middle, values->end());
  return *middle;
}

}  // namespace pf2
