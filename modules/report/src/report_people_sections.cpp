// The people: their tracks from above, a table per person and the detector's counts over time.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "html_text.h"
#include "pf2/humans/human_track.h"
#include "report_context.h"
#include "svg_plot.h"

namespace pf2 {
namespace report {

namespace {

constexpr size_t kMaxLegendPeople = 12;  // more tracks: ids beside the tracks only
constexpr double kSameFrame = 1e-3;      // seconds: a track point and a frame this close coincide

std::string personSwatch(int id) {
  return "<span class=\"swatch\" style=\"background:" + colourHex(personColour(id)) + "\"></span>" +
         std::to_string(id);
}

// Why there is nothing to show, or empty when there are people.
std::string noPeopleReason(const SlamResult& result) {
  if (!result.has_humans) return "No people: no detector ran or people tracking was off.";
  if (result.humans.empty()) return "No people were tracked.";
  return "";
}

void addTrack(const ReportContext& c, const HumanTrack& track, bool in_legend, SvgPlot* plot) {
  std::vector<Eigen::Vector2d> points;
  std::vector<double> times;
  for (const HumanTrackPoint& point : track.points) {
    if (!point.p_w.allFinite() || !std::isfinite(point.timestamp)) continue;
    points.push_back(c.view.project(c.view.fromEstimate(point.p_w)));
    times.push_back(point.timestamp);
  }
  if (points.empty()) return;
  const std::string colour = colourHex(personColour(track.id));
  plot->addLine(in_legend ? "person " + std::to_string(track.id) : "", breakAtGaps(times, points), colour, 1.8);
  plot->addMarkers("", {points.front()}, colour, SvgPlot::Marker::kCircle, 3.5);
  plot->addLabel(points.back(), std::to_string(track.id), colour);
}

std::string peoplePlot(const ReportContext& c) {
  SvgPlot plot("people-top-view", "People's tracks from above (circle: first seen; label: id, last seen)", 720,
               640);
  plot.setEqualAspect();
  plot.setAxisLabels(c.view.uLabel(), c.view.vLabel());
  std::vector<Eigen::Vector2d> camera;
  for (const StampedPose& pose : c.estimate) {
    camera.push_back(c.view.project(c.view.fromEstimate(pose.T_w_c.translation())));
  }
  plot.addLine("camera", camera, "#6e7681", 1.0, true);
  const bool legend = c.result->humans.size() <= kMaxLegendPeople;
  for (const HumanTrack& track : c.result->humans) addTrack(c, track, legend, &plot);
  return plot.hasData() ? plot.render() : note("No finite positions to draw.");
}

double pathLength(const HumanTrack& track) {
  double length = 0.0;
  for (size_t k = 1; k < track.points.size(); ++k) {
    const double step = (track.points[k].p_w - track.points[k - 1].p_w).norm();
    if (std::isfinite(step)) length += step;
  }
  return length;
}

std::string peopleTable(const ReportContext& c) {
  HtmlTable table({"id", "first seen (s)", "last seen (s)", "frames seen", "path (m)"});
  for (const HumanTrack& track : c.result->humans) {
    if (track.points.empty()) continue;
    table.addRow({personSwatch(track.id), fixed(relativeTime(c, track.points.front().timestamp), 2),
                  fixed(relativeTime(c, track.points.back().timestamp), 2), std::to_string(track.points.size()),
                  fixed(pathLength(track), 2)});
  }
  return table.render();
}

// Frame times: every frame with a status, else every time a person was seen.
std::vector<double> frameTimes(const SlamResult& result, const std::vector<double>& seen) {
  std::vector<double> times;
  for (const auto& frame : result.frame_status) {
    if (std::isfinite(frame.first)) times.push_back(frame.first);
  }
  if (times.empty()) times = seen;
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
  return times;
}

// People tracked in each frame: (seconds since the origin, count).
std::vector<Eigen::Vector2d> peoplePerFrame(const ReportContext& c) {
  std::vector<double> seen;
  for (const HumanTrack& track : c.result->humans) {
    for (const HumanTrackPoint& point : track.points) {
      if (std::isfinite(point.timestamp)) seen.push_back(point.timestamp);
    }
  }
  std::sort(seen.begin(), seen.end());
  std::vector<Eigen::Vector2d> counts;
  for (const double t : frameTimes(*c.result, seen)) {
    const auto lo = std::lower_bound(seen.begin(), seen.end(), t - kSameFrame);
    const auto hi = std::upper_bound(seen.begin(), seen.end(), t + kSameFrame);
    counts.emplace_back(relativeTime(c, t), static_cast<double>(hi - lo));
  }
  return counts;
}

std::string detectorTable(const ReportContext& c, const std::vector<Eigen::Vector2d>& counts) {
  double total = 0.0, most = 0.0;
  int with_people = 0;
  for (const Eigen::Vector2d& count : counts) {
    total += count.y();
    most = std::max(most, count.y());
    with_people += count.y() > 0.0 ? 1 : 0;
  }
  const double frames = static_cast<double>(counts.size());
  const SlamResult& r = *c.result;
  return keyValueTable({{"Detector", r.summary.detector.empty() ? "none" : r.summary.detector},
                        {"People tracks", std::to_string(r.humans.size())},
                        {"Person sightings (track points)", fixed(total, 0)},
                        {"Frames with people", std::to_string(with_people) + " of " + fixed(frames, 0)},
                        {"People per frame: mean / most", fixed(frames > 0 ? total / frames : 0.0, 2) + " / " +
                                                              fixed(most, 0)},
                        {"Body tracks", std::to_string(r.bodies.size())}});
}

}  // namespace

std::string peopleSection(const ReportContext& c) {
  const std::string reason = noPeopleReason(*c.result);
  if (!reason.empty()) return section("people", "People", note(reason));
  return section("people", "People", peoplePlot(c) + peopleTable(c));
}

std::string detectorSection(const ReportContext& c) {
  const std::string reason = noPeopleReason(*c.result);
  if (!reason.empty()) return section("detector", "Detector statistics", note(reason));
  const std::vector<Eigen::Vector2d> counts = peoplePerFrame(c);
  SvgPlot plot("people-per-frame", "People tracked per frame", 960, 260);
  plot.setAxisLabels("time (s)", "people");
  plot.setYFromZero();
  plot.addLine("people in the frame", counts, "#d2a8ff", 1.4);
  const std::string figure = plot.hasData() ? plot.render() : note("No frame to count people in.");
  return section("detector", "Detector statistics", figure + detectorTable(c, counts));
}

}  // namespace report
}  // namespace pf2
