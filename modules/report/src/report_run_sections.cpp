// The run's summary, its per-stage times and its settings.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "html_text.h"
#include "report_context.h"
#include "svg_plot.h"

namespace pf2 {
namespace report {

namespace {

// Stages timed once per frame, in pipeline order; others (load, map, exports) go to the table only.
const std::vector<std::string> kPerFrameStages = {"detect", "filter", "track", "humans", "predict", "frame"};
const std::vector<std::string> kStageColours = {"#f778ba", "#d2a8ff", "#58a6ff", "#3fb950", "#e3b341", "#e6edf3"};

std::string count(int value) { return std::to_string(value); }

std::vector<std::pair<std::string, std::string>> summaryRows(const ReportContext& c) {
  const SlamRunSummary& s = c.result->summary;
  std::vector<std::pair<std::string, std::string>> rows = {
      {"Sequence", c.input->title.empty() ? "(untitled)" : c.input->title},
      {"Detector", s.detector.empty() ? "none" : s.detector},
      {"Frames", count(s.frames)},
      {"Posed (tracked, bridged or relocalised)", count(s.tracked)},
      {"Bridged", count(s.bridged)},
      {"Relocalised", count(s.relocalised)},
      {"Lost", count(s.lost)},
      {"Keyframes", count(s.keyframes)},
      {"Loop closures", count(s.loop_closures)},
      {"Local edges", count(s.local_edges)},
      {"Frames per second (end to end)", fixed(s.fps, 2)},
      {"Run time (s)", fixed(s.seconds, 2)},
      {"Trajectory smoothing, acceleration noise (m/s²)", s.acceleration_noise > 0 ? fixed(s.acceleration_noise, 2) : "none"},
      {"Body fits offered / skipped", count(s.body_fits_offered) + " / " + count(s.body_fits_skipped)},
      {"People tracks", c.result->has_humans ? count(static_cast<int>(c.result->humans.size())) : "not tracked"},
  };
  return rows;
}

void addAccuracyRows(const ReportContext& c, std::vector<std::pair<std::string, std::string>>* rows) {
  if (!c.input->ground_truth) return;
  if (!c.has_ate) {
    rows->push_back({"Ground truth", "not used: " + c.ate_note});
    return;
  }
  const ErrorStatistics& t = c.ate.translation;
  rows->push_back({"ATE RMSE / mean / max (m)", fixed(t.rmse, 4) + " / " + fixed(t.mean, 4) + " / " + fixed(t.max, 4)});
  rows->push_back({"Poses compared with the ground truth", count(t.count)});
}

// The per-frame stages as lines against the call index; the y axis is cut above the largest
// 99.5th percentile when a few calls (the first frame's warm-up) would flatten everything else.
std::string stagePlot(const StageStats& stats, std::string* caption) {
  SvgPlot plot("stage-times", "Time per call of each per-frame stage", 960, 340);
  plot.setAxisLabels("call (about one per frame)", "ms");
  plot.setYFromZero();
  double typical_top = 0.0, largest = 0.0;
  for (size_t k = 0; k < kPerFrameStages.size(); ++k) {
    std::vector<double> finite;
    std::vector<Eigen::Vector2d> points;
    for (const double ms : stats.samples(kPerFrameStages[k])) {
      // A non-finite duration is left out as a gap (the line breaks), keeping the call index.
      const double shown = std::isfinite(ms) ? ms : std::numeric_limits<double>::quiet_NaN();
      points.emplace_back(static_cast<double>(points.size()), shown);
      if (std::isfinite(ms)) finite.push_back(ms);
    }
    if (finite.empty()) continue;
    plot.addLine(kPerFrameStages[k], points, kStageColours[k], 1.2);
    typical_top = std::max(typical_top, percentile(finite, 99.5));
    largest = std::max(largest, *std::max_element(finite.begin(), finite.end()));
  }
  if (largest > 1.5 * typical_top && typical_top > 0.0) {
    plot.setYRange(0.0, 1.2 * typical_top);
    *caption = "The y axis is cut at " + fixed(1.2 * typical_top, 1) + " ms; the slowest call took " +
               fixed(largest, 1) + " ms (see max in the table).";
  }
  return plot.hasData() ? plot.render() : "";
}

std::string stageTable(const StageStats& stats) {
  HtmlTable table({"stage", "calls", "median ms", "p90 ms", "mean ms", "max ms", "total s"});
  for (const std::string& stage : stats.stages()) {
    const StageSummary s = stats.summary(stage);
    table.addRow({escapeHtml(stage), std::to_string(s.count), fixed(s.median_ms, 2), fixed(s.p90_ms, 2),
                  fixed(s.mean_ms, 2), fixed(s.max_ms, 2), fixed(s.total_ms / 1000.0, 2)});
  }
  return table.render();
}

}  // namespace

std::string summarySection(const ReportContext& context) {
  auto rows = summaryRows(context);
  addAccuracyRows(context, &rows);
  return section("summary", "Run summary", keyValueTable(rows));
}

std::string stageSection(const ReportContext& context) {
  const StageStats& stats = *context.input->stages;
  if (stats.stages().empty()) return section("stages", "Time per stage", note("No stage timings were recorded."));
  std::string caption;
  std::string body = stagePlot(stats, &caption);
  if (body.empty()) body = note("No per-frame stage was timed (only the stages in the table).");
  if (!caption.empty()) body += note(caption);
  return section("stages", "Time per stage", body + stageTable(stats));
}

std::string settingsSection(const ReportContext& context) {
  const auto& settings = context.input->settings;
  if (settings.empty()) return section("settings", "Settings", note("No settings were passed to the report."));
  const std::string body = "<details>\n<summary>" + std::to_string(settings.size()) +
                           " settings (click to open)</summary>\n" + keyValueTable(settings) + "</details>\n";
  return section("settings", "Settings", body);
}

}  // namespace report
}  // namespace pf2
