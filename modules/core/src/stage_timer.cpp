#include "pf2/core/stage_timer.h"

#include <algorithm>
#include <cstdio>
#include <numeric>
#include <sstream>

namespace pf2 {

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double rank = std::clamp(p, 0.0, 100.0) / 100.0 * (values.size() - 1);
  const size_t low = static_cast<size_t>(rank);
  const size_t high = std::min(low + 1, values.size() - 1);
  const double fraction = rank - low;
  return values[low] * (1.0 - fraction) + values[high] * fraction;
}

void StageStats::add(const std::string& stage, double milliseconds) {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = samples_.find(stage);
  if (it == samples_.end()) {
    order_.push_back(stage);
    it = samples_.emplace(stage, std::vector<double>()).first;
  }
  it->second.push_back(milliseconds);
}

StageSummary StageStats::summary(const std::string& stage) const {
  std::vector<double> values;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = samples_.find(stage);
    if (it == samples_.end()) return {};
    values = it->second;
  }
  StageSummary s;
  s.count = static_cast<int>(values.size());
  s.total_ms = std::accumulate(values.begin(), values.end(), 0.0);
  s.mean_ms = s.total_ms / s.count;
  s.max_ms = *std::max_element(values.begin(), values.end());
  s.median_ms = percentile(values, 50.0);
  s.p90_ms = percentile(std::move(values), 90.0);
  return s;
}

std::vector<double> StageStats::samples(const std::string& stage) const {
  std::lock_guard<std::mutex> lock(mutex_);
  const auto it = samples_.find(stage);
  return it == samples_.end() ? std::vector<double>() : it->second;
}

std::vector<std::string> StageStats::stages() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return order_;
}

std::string StageStats::toJson() const {
  std::ostringstream out;
  out << "{";
  bool first = true;
  for (const std::string& stage : stages()) {
    const StageSummary s = summary(stage);
    char buffer[256];
    std::snprintf(buffer, sizeof(buffer),
                  "\"count\":%d,\"median_ms\":%.4f,\"p90_ms\":%.4f,\"mean_ms\":%.4f,\"max_ms\":%.4f",
                  s.count, s.median_ms, s.p90_ms, s.mean_ms, s.max_ms);
    out << (first ? "" : ",") << "\"" << stage << "\":{" << buffer << "}";
    first = false;
  }
  out << "}";
  return out.str();
}

}  // namespace pf2
