#include "pf2/eval/error_statistics.h"

#include <algorithm>
#include <cmath>

#include "pf2/core/stage_timer.h"

namespace pf2 {

ErrorStatistics computeErrorStatistics(const std::vector<double>& errors) {
  ErrorStatistics s;
  if (errors.empty()) return s;
  s.count = static_cast<int>(errors.size());
  double sum = 0.0, sum_squares = 0.0;
  for (double e : errors) {
    sum += e;
    sum_squares += e * e;
  }
  s.mean = sum / s.count;
  s.rmse = std::sqrt(sum_squares / s.count);
  s.std = std::sqrt(std::max(0.0, sum_squares / s.count - s.mean * s.mean));
  s.min = *std::min_element(errors.begin(), errors.end());
  s.max = *std::max_element(errors.begin(), errors.end());
  s.median = percentile(errors, 50.0);
  return s;
}

}  // namespace pf2
