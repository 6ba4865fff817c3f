// The camera's motion: the trajectory from above, the error over time and each frame's status.
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

constexpr double kSameFrame = 1e-3;  // seconds: a status and a pose this close belong to one frame
constexpr size_t kMaxRunRows = 40;   // rows of the table of non-tracked stretches

// A stretch of consecutive frames with one status.
struct StatusRun {
  TrackStatus status = TrackStatus::kOk;
  double begin = 0.0, end = 0.0;  // seconds since the time origin; end = the next frame's time
  int frames = 0;
};

// Index of the pose at `timestamp` in poses sorted by time, or -1.
int poseAt(const Trajectory& poses, double timestamp) {
  const auto it = std::lower_bound(poses.begin(), poses.end(), timestamp - kSameFrame,
                                   [](const StampedPose& p, double t) { return p.timestamp < t; });
  if (it == poses.end() || it->timestamp > timestamp + kSameFrame) return -1;
  return static_cast<int>(it - poses.begin());
}

// Frames' statuses grouped into runs; the last frame lasts as long as the median frame interval.
std::vector<StatusRun> statusRuns(const ReportContext& c) {
  std::vector<std::pair<double, TrackStatus>> frames;
  for (const auto& frame : c.result->frame_status) {
    if (std::isfinite(frame.first)) frames.emplace_back(relativeTime(c, frame.first), frame.second);
  }
  std::vector<double> steps;
  for (size_t k = 1; k < frames.size(); ++k) steps.push_back(frames[k].first - frames[k - 1].first);
  const double last_step = steps.empty() ? 1.0 / 30.0 : std::max(percentile(steps, 50.0), 0.0);
  std::vector<StatusRun> runs;
  for (size_t k = 0; k < frames.size(); ++k) {
    const double end = k + 1 < frames.size() ? frames[k + 1].first : frames[k].first + last_step;
    if (runs.empty() || runs.back().status != frames[k].second) {
      runs.push_back({frames[k].second, frames[k].first, end, 0});
    }
    runs.back().end = end;
    ++runs.back().frames;
  }
  return runs;
}

// Positions on the view's plane, the line broken where poses are missing.
std::vector<Eigen::Vector2d> projected(const ReportContext& c, const Trajectory& poses, bool estimate) {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> times;
  for (const StampedPose& pose : poses) {
    const Eigen::Vector3d p = pose.T_w_c.translation();
    points.push_back(c.view.project(estimate ? c.view.fromEstimate(p) : p));
    times.push_back(pose.timestamp);
  }
  return breakAtGaps(times, points);
}

// Bridged and relocalised frames at their poses, and the last pose before each loss.
void addStatusMarkers(const ReportContext& c, SvgPlot* plot) {
  std::vector<Eigen::Vector2d> bridged, relocalised, lost_after;
  const auto at = [&c](int pose) { return c.view.project(c.view.fromEstimate(c.estimate[pose].T_w_c.translation())); };
  int last_pose = -1;
  TrackStatus previous = TrackStatus::kOk;
  for (const auto& [timestamp, status] : c.result->frame_status) {
    const int pose = hasPose(status) ? poseAt(c.estimate, timestamp) : -1;
    if (status == TrackStatus::kBridged && pose >= 0) bridged.push_back(at(pose));
    if (status == TrackStatus::kRelocalised && pose >= 0) relocalised.push_back(at(pose));
    if (status == TrackStatus::kLost && previous != TrackStatus::kLost && last_pose >= 0) {
      lost_after.push_back(at(last_pose));
    }
    if (pose >= 0) last_pose = pose;
    previous = status;
  }
  const auto add = [plot](const char* name, const std::vector<Eigen::Vector2d>& points, TrackStatus status,
                          SvgPlot::Marker marker, double radius) {
    if (!points.empty()) plot->addMarkers(name, points, statusColour(status), marker, radius);
  };
  add("bridged", bridged, TrackStatus::kBridged, SvgPlot::Marker::kCircle, 3.0);
  add("relocalised", relocalised, TrackStatus::kRelocalised, SvgPlot::Marker::kDiamond, 5.0);
  add("lost after this pose", lost_after, TrackStatus::kLost, SvgPlot::Marker::kCross, 5.0);
}

std::string trajectoryCaption(const ReportContext& c) {
  const TopView& v = c.view;
  const std::string plane = v.axisLabel(v.axis_u).substr(0, 1) + "-" + v.axisLabel(v.axis_v).substr(0, 1);
  const std::string flipped = v.flip_v ? "; " + v.axisLabel(v.axis_v).substr(0, 1) + " drawn downwards" : "";
  const std::string world = c.has_ate ? "the ground truth's world" : "the estimate's world";
  const std::string why = v.up_axis >= 0
                              ? "vertical: " + v.axisLabel(v.up_axis).substr(0, 1) + ", from the cameras' orientation"
                              : std::string(c.has_ate ? "its two axes of largest variance"
                                                      : "its two axes of largest extent");
  std::string text = "Seen from above: the " + plane + " plane of " + world + " (" + why + flipped + ").";
  if (c.has_ate) text += " The estimate is aligned to the ground truth as for the ATE (rigid, least squares).";
  if (c.input->ground_truth && !c.has_ate) text += " Ground truth not used: " + c.ate_note;
  return text;
}

std::string statusTable(const std::vector<StatusRun>& runs) {
  HtmlTable table({"status", "from (s)", "to (s)", "frames"});
  size_t rows = 0, left_out = 0;
  for (const StatusRun& run : runs) {
    if (run.status == TrackStatus::kOk) continue;
    if (rows++ >= kMaxRunRows) {
      ++left_out;
      continue;
    }
    table.addRow({"<span class=\"swatch\" style=\"background:" + statusColour(run.status) + "\"></span>" +
                      statusName(run.status),
                  fixed(run.begin, 2), fixed(run.end, 2), std::to_string(run.frames)});
  }
  if (table.empty()) return note("Every frame was tracked.");
  return table.render() + (left_out ? note("... and " + std::to_string(left_out) + " more stretches.") : "");
}

}  // namespace

std::string trajectorySection(const ReportContext& c) {
  SvgPlot plot("top-view", "Camera trajectory from above", 720, 640);
  plot.setEqualAspect();
  plot.setAxisLabels(c.view.uLabel(), c.view.vLabel());
  if (c.has_ate) plot.addLine("ground truth", projected(c, c.ground_truth, false), "#8b949e", 1.5, true);
  const std::vector<Eigen::Vector2d> estimate = projected(c, c.estimate, true);
  plot.addLine(c.has_ate ? "estimate (aligned)" : "estimate", estimate, "#e6edf3", 1.6);
  if (!estimate.empty()) {
    plot.addMarkers("start", {estimate.front()}, statusColour(TrackStatus::kOk), SvgPlot::Marker::kCircle, 5.0);
  }
  addStatusMarkers(c, &plot);
  if (!plot.hasData()) return section("trajectory", "Trajectory", note("No poses: the camera was never tracked."));
  return section("trajectory", "Trajectory", plot.render() + note(trajectoryCaption(c)));
}

std::string errorSection(const ReportContext& c) {
  const std::string title = "Error over time";
  if (!c.input->ground_truth) return section("error", title, note("No ground truth was given."));
  if (!c.has_ate) return section("error", title, note("Ground truth not used: " + c.ate_note));
  SvgPlot plot("ate-over-time", "Absolute trajectory error per pose", 960, 300);
  plot.setAxisLabels("time (s)", "ATE (m)");
  plot.setYFromZero();
  std::vector<Eigen::Vector2d> errors;
  std::vector<double> times;
  for (size_t k = 0; k < c.ate.matches.size() && k < c.ate.errors.size(); ++k) {
    times.push_back(relativeTime(c, c.estimate[c.ate.matches[k].second].timestamp));
    errors.emplace_back(times.back(), c.ate.errors[k]);
  }
  plot.addLine("error", breakAtGaps(times, errors), "#e3b341", 1.4);
  if (times.size() >= 2) {
    const double rmse = c.ate.translation.rmse;
    plot.addLine("RMSE " + fixed(rmse, 4) + " m", {{times.front(), rmse}, {times.back(), rmse}}, "#f85149", 1.2, true);
  }
  return section("error", title, plot.render());
}

std::string statusSection(const ReportContext& c) {
  const std::vector<StatusRun> runs = statusRuns(c);
  if (runs.empty()) return section("status", "Tracking status", note("No frame status was recorded."));
  SvgPlot plot("status-strip", "Tracking status of every frame", 960, 130);
  plot.setAxisLabels("time (s)", "");
  plot.hideYAxis();
  for (const TrackStatus status : allStatuses()) {
    std::vector<std::pair<double, double>> spans;
    int frames = 0;
    for (const StatusRun& run : runs) {
      if (run.status != status) continue;
      spans.emplace_back(run.begin, run.end);
      frames += run.frames;
    }
    if (!spans.empty()) {
      plot.addBands(std::string(statusName(status)) + " (" + std::to_string(frames) + ")", spans,
                    statusColour(status));
    }
  }
  return section("status", "Tracking status", plot.render() + statusTable(runs));
}

}  // namespace report
}  // namespace pf2
