#pragma once
// A hand-made run for the report's tests and its fixture: a camera on a loop (z-up world) with
// bridged, lost and relocalised frames, two people walking, per-frame stage timings with a slow
// first call, settings, and the ground truth the estimate drifted from.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "pf2/report/run_report.h"

namespace pf2 {
namespace test {

struct SampleRun {
  SlamResult result;
  StageStats stages;
  Trajectory ground_truth;
  std::vector<std::pair<std::string, std::string>> settings;

  // Points into this object, which must outlive the returned value.
  RunReportInput input(bool with_ground_truth = true) const;
};

struct SampleOptions {
  int frames = 300;          // at 30 Hz; the fixed stretches of bridged/lost frames need >= 260
  std::uint64_t seed = 7;
  double start_time = 1700000000.0;
};

// Fills *run (StageStats cannot be moved, so the caller owns the object).
void makeSampleRun(const SampleOptions& options, SampleRun* run);

}  // namespace test
}  // namespace pf2
