#pragma once
// A small chart builder for the run report: lines, markers and vertical bands on linear axes with
// ticks, labels and a legend, rendered as one inline <svg class="plot"> element. Drawn on the
// server so the page needs no script and fetches nothing; the page's CSS styles the axes.
//
//   SvgPlot plot("stage-times", "Time per frame", 900, 320);
//   plot.setAxisLabels("frame", "ms");
//   plot.addLine("track", points, "#4c9aff");
//   html += plot.render();
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

namespace pf2 {
namespace report {

class SvgPlot {
 public:
  enum class Marker { kCircle, kCross, kDiamond };

  // id: the element's id, unique on the page; width and height in CSS pixels without the legend
  // (the legend's rows are added below).
  SvgPlot(std::string id, std::string title, int width, int height);

  void setAxisLabels(std::string x_label, std::string y_label);
  // One unit is as long on both axes (top views: a circle stays round).
  void setEqualAspect() { equal_aspect_ = true; }
  // Fixed y range; what lies outside is clipped at the plot area's edge.
  void setYRange(double lo, double hi);
  // The y axis starts at 0 (durations, counts) unless values go below it.
  void setYFromZero() { y_from_zero_ = true; }
  // No y ticks or y label (a strip whose height means nothing).
  void hideYAxis() { show_y_axis_ = false; }

  // Non-finite points are skipped: a line breaks there.
  void addLine(const std::string& name, const std::vector<Eigen::Vector2d>& points, const std::string& colour,
               double width = 1.5, bool dashed = false);
  void addMarkers(const std::string& name, const std::vector<Eigen::Vector2d>& points, const std::string& colour,
                  Marker marker, double radius = 4.0);
  // x intervals [first, second] over the full height of the plot area.
  void addBands(const std::string& name, const std::vector<std::pair<double, double>>& spans,
                const std::string& colour);
  // Text beside a data point (a person's id at the end of the track).
  void addLabel(const Eigen::Vector2d& at, const std::string& text, const std::string& colour);

  // True when some series has a finite point (or band).
  bool hasData() const;
  std::string render() const;

  struct Layout;  // data-to-pixel mapping, computed by render()

 private:
  enum class Kind { kLine, kMarkers, kBands };
  struct Series {
    Kind kind = Kind::kLine;
    std::string name;
    std::string colour;
    std::vector<Eigen::Vector2d> points;  // bands: (x0, x1) per point
    double size = 1.5;                    // line width or marker radius
    bool dashed = false;
    Marker marker = Marker::kCircle;
  };
  struct Label {
    Eigen::Vector2d at;
    std::string text;
    std::string colour;
  };

  Layout layout() const;
  std::string renderAxes(const Layout& layout) const;
  std::string renderSeries(const Series& series, const Layout& layout) const;
  std::string renderLabels(const Layout& layout) const;
  std::string renderLegend(const Layout& layout) const;
  std::vector<std::pair<const Series*, Eigen::Vector2d>> legendPlaces(double left, double top) const;

  std::string id_, title_, x_label_, y_label_;
  int width_, height_;
  bool equal_aspect_ = false, y_from_zero_ = false, show_y_axis_ = true, fixed_y_ = false;
  double y_lo_ = 0.0, y_hi_ = 1.0;
  std::vector<Series> series_;
  std::vector<Label> labels_;
};

}  // namespace report
}  // namespace pf2
