#pragma once
// report.html: one self-contained page (inline SVG, no script, nothing fetched) with a run's
// summary, per-stage times, the trajectory from above, the error over time (with ground truth),
// each frame's tracking status, the people's tracks, detector statistics and the settings.
// docs/report.md describes the page.
//
//   RunReportInput input;
//   input.title = source.description();
//   input.result = &result;
//   input.stages = &slam.stats();
//   writeRunReport(out_dir + "/report.html", input);
#include <string>
#include <utility>
#include <vector>

#include "pf2/core/pose.h"
#include "pf2/core/stage_timer.h"
#include "pf2/slam/slam_system.h"

namespace pf2 {

struct RunReportInput {
  std::string title;  // e.g. the sequence's description
  // Every setting as (key, value), shown in this order in a table.
  std::vector<std::pair<std::string, std::string>> settings;
  const SlamResult* result = nullptr;  // required: summary, trajectory, frame_status, humans
  const StageStats* stages = nullptr;  // required: per-stage timings (StageStats::samples)
  // Optional: ground-truth camera poses (T_w_c, TUM convention) in their own world frame; the
  // estimate is aligned to it (computeAte) for the top view and the error over time.
  const Trajectory* ground_truth = nullptr;
};

// Writes the page atomically (temporary file + rename). Throws pf2::Error naming the path when
// result or stages is missing or the file cannot be written. Degenerate input (no poses, no
// stages, no people, ground truth that cannot be associated) gives a page that says so.
void writeRunReport(const std::string& path, const RunReportInput& input);

}  // namespace pf2
