#pragma once
#include <vector>

namespace pf2 {

// Summary of a list of non-negative errors, as the TUM benchmark tools print it.
struct ErrorStatistics {
  int count = 0;
  double rmse = 0.0;
  double mean = 0.0;
  double median = 0.0;
  double std = 0.0;  // population standard deviation (numpy's default, as the TUM tools use)
  double min = 0.0;
  double max = 0.0;
};

ErrorStatistics computeErrorStatistics(const std::vector<double>& errors);

}  // namespace pf2
