#pragma once
// Per-stage wall-clock statistics for the run report.
//
//   StageStats stats;
//   { ScopedStageTimer t(&stats, "filter"); filter.run(...); }
//   stats.summary("filter").median_ms;
#include <chrono>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace pf2 {

struct StageSummary {
  int count = 0;
  double median_ms = 0.0;
  double p90_ms = 0.0;
  double mean_ms = 0.0;
  double max_ms = 0.0;
  double total_ms = 0.0;
};

// Collects durations per stage name. Thread safe.
class StageStats {
 public:
  void add(const std::string& stage, double milliseconds);
  StageSummary summary(const std::string& stage) const;  // all zero for an unknown stage
  std::vector<std::string> stages() const;                // in order of first use
  // Every duration of a stage, in the order they were added (per frame for a stage timed once a
  // frame); empty for an unknown stage.
  std::vector<double> samples(const std::string& stage) const;
  // {"stage": {"count":..,"median_ms":..,"p90_ms":..,"mean_ms":..,"max_ms":..}, ...}
  std::string toJson() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::string, std::vector<double>> samples_;
  std::vector<std::string> order_;
};

// Adds the time between construction and destruction to `stats` under `stage`.
class ScopedStageTimer {
 public:
  ScopedStageTimer(StageStats* stats, std::string stage)
      : stats_(stats), stage_(std::move(stage)), start_(std::chrono::steady_clock::now()) {}
  ~ScopedStageTimer() {
    const auto end = std::chrono::steady_clock::now();
    stats_->add(stage_, std::chrono::duration<double, std::milli>(end - start_).count());
  }
  ScopedStageTimer(const ScopedStageTimer&) = delete;
  ScopedStageTimer& operator=(const ScopedStageTimer&) = delete;

 private:
  StageStats* stats_;
  std::string stage_;
  std::chrono::steady_clock::time_point start_;
};

// Percentile (0..100) by linear interpolation between order statistics; 0 for an empty list.
double percentile(std::vector<double> values, double p);

}  // namespace pf2
