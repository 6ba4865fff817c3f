#include "svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <sstream>

#include "html_text.h"

namespace pf2 {
namespace report {

struct SvgPlot::Layout {
  double x_lo = 0, x_hi = 1, y_lo = 0, y_hi = 1;  // data range shown
  double left = 0, top = 0, right = 1, bottom = 1;  // plot area, pixels
  int total_height = 0;                             // with the legend's rows

  Eigen::Vector2d pixel(const Eigen::Vector2d& p) const {
    // SVG rows grow downwards: flip y so larger values are higher up.
    return {left + (p.x() - x_lo) / (x_hi - x_lo) * (right - left),
            bottom - (p.y() - y_lo) / (y_hi - y_lo) * (bottom - top)};
  }
};

namespace {

constexpr double kLegendRow = 18.0;  // pixels per legend row
constexpr double kLegendTop = 8.0;   // first legend row below the nominal height
constexpr double kMinPixelStep = 0.7;  // closer points of a line add nothing visible

struct Range {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  void add(double v) {
    if (!std::isfinite(v)) return;
    lo = std::min(lo, v);
    hi = std::max(hi, v);
  }
  bool valid() const { return lo <= hi; }
  double span() const { return hi - lo; }
};

// A range of zero width (one point, a constant series) gets room around it so it can be drawn.
void widen(Range* r) {
  if (r->span() > 1e-9 * std::max(1.0, std::abs(r->lo))) return;
  const double half = std::max(0.5, std::abs(r->lo) * 0.1);
  r->lo -= half;
  r->hi += half;
}

void pad(Range* r, double fraction) {
  const double margin = r->span() * fraction;
  r->lo -= margin;
  r->hi += margin;
}

// Grows the range that has fewer units per pixel so both axes have the same scale.
void equalise(Range* x, Range* y, double width, double height) {
  const double per_pixel = std::max(x->span() / width, y->span() / height);
  const auto grow = [per_pixel](Range* r, double pixels) {
    const double centre = 0.5 * (r->lo + r->hi);
    r->lo = centre - 0.5 * per_pixel * pixels;
    r->hi = centre + 0.5 * per_pixel * pixels;
  };
  grow(x, width);
  grow(y, height);
}

// 1, 2 or 5 times a power of ten, giving about `target` ticks over the span.
double niceStep(double span, double target) {
  const double raw = span / std::max(target, 1.0);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (const double factor : {1.0, 2.0, 5.0}) {
    if (factor * magnitude >= raw) return factor * magnitude;
  }
  return 10.0 * magnitude;
}

std::vector<double> ticks(double lo, double hi, double step) {
  std::vector<double> values;
  for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step && values.size() < 100; ++k) {
    values.push_back(std::abs(k * step) < 1e-12 * step ? 0.0 : k * step);
  }
  return values;
}

std::string tickText(double value, double step) {
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step) + 1e-9)));
  return fixed(value, decimals);
}

// Pixel coordinate with one decimal: enough for a screen, small in the file.
std::string px(double value) { return fixed(value, 1); }
std::string at(const Eigen::Vector2d& p) { return px(p.x()) + "," + px(p.y()); }

bool nonDecreasingX(const std::vector<Eigen::Vector2d>& points) {
  return std::is_sorted(points.begin(), points.end(),
                        [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() < b.x(); });
}

// A long time series keeps, per pixel column, its first, lowest, highest and last point: the
// drawing looks the same (spikes stay) and the file stays small for runs of many frames.
std::vector<Eigen::Vector2d> thinColumns(const std::vector<Eigen::Vector2d>& pixels) {
  std::vector<Eigen::Vector2d> out;
  for (size_t begin = 0; begin < pixels.size();) {
    size_t end = begin;
    size_t low = begin, high = begin;
    while (end < pixels.size() && std::floor(pixels[end].x()) == std::floor(pixels[begin].x())) {
      if (pixels[end].y() < pixels[low].y()) low = end;
      if (pixels[end].y() > pixels[high].y()) high = end;
      ++end;
    }
    std::set<size_t> keep = {begin, low, high, end - 1};
    for (const size_t k : keep) out.push_back(pixels[k]);
    begin = end;
  }
  return out;
}

// "M x,y L x,y ..." with a new "M" after every non-finite point (a gap in the data).
std::string linePath(const std::vector<Eigen::Vector2d>& points, const SvgPlot::Layout& layout) {
  std::vector<std::vector<Eigen::Vector2d>> runs(1);
  for (const Eigen::Vector2d& p : points) {
    if (!p.allFinite()) {
      if (!runs.back().empty()) runs.emplace_back();
      continue;
    }
    runs.back().push_back(layout.pixel(p));
  }
  std::string d;
  for (std::vector<Eigen::Vector2d>& run : runs) {
    if (run.empty()) continue;  // the data ended on a gap
    if (run.size() > 2 * static_cast<size_t>(layout.right - layout.left) && nonDecreasingX(run)) {
      run = thinColumns(run);
    }
    Eigen::Vector2d drawn = run.front();
    for (size_t k = 0; k < run.size(); ++k) {
      const bool last = k + 1 == run.size();
      if (k > 0 && !last && (run[k] - drawn).norm() < kMinPixelStep) continue;
      d += (k == 0 ? "M" : "L") + at(run[k]);
      drawn = run[k];
    }
  }
  return d;
}

std::string markerPath(const Eigen::Vector2d& c, SvgPlot::Marker marker, double r) {
  const std::string R = px(r), D = px(2 * r);
  switch (marker) {
    case SvgPlot::Marker::kCross:
      return "M" + at(c - Eigen::Vector2d(r, r)) + "l" + D + "," + D + "M" + at(c + Eigen::Vector2d(-r, r)) +
             "l" + D + ",-" + D;
    case SvgPlot::Marker::kDiamond:
      return "M" + at(c - Eigen::Vector2d(0, r)) + "l" + R + "," + R + "l-" + R + "," + R + "l-" + R + ",-" + R +
             "Z";
    case SvgPlot::Marker::kCircle:
    default:
      return "M" + at(c - Eigen::Vector2d(r, 0)) + "a" + R + "," + R + " 0 1 0 " + D + ",0a" + R + "," + R +
             " 0 1 0 -" + D + ",0Z";
  }
}

// Stroke and fill attributes of a series' element (or of its legend swatch).
std::string paint(const std::string& colour, bool stroked, double width, bool dashed) {
  if (!stroked) return "fill=\"" + escapeHtml(colour) + "\" stroke=\"none\"";
  return "fill=\"none\" stroke=\"" + escapeHtml(colour) + "\" stroke-width=\"" + px(width) +
         "\" stroke-linejoin=\"round\" stroke-linecap=\"round\"" + (dashed ? " stroke-dasharray=\"6 4\"" : "");
}

}  // namespace

SvgPlot::SvgPlot(std::string id, std::string title, int width, int height)
    : id_(std::move(id)), title_(std::move(title)), width_(std::max(width, 120)), height_(std::max(height, 80)) {}

void SvgPlot::setAxisLabels(std::string x_label, std::string y_label) {
  x_label_ = std::move(x_label);
  y_label_ = std::move(y_label);
}

void SvgPlot::setYRange(double lo, double hi) {
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(hi > lo)) return;  // keep the data's range
  fixed_y_ = true;
  y_lo_ = lo;
  y_hi_ = hi;
}

void SvgPlot::addLine(const std::string& name, const std::vector<Eigen::Vector2d>& points, const std::string& colour,
                      double width, bool dashed) {
  series_.push_back({Kind::kLine, name, colour, points, width, dashed, Marker::kCircle});
}

void SvgPlot::addMarkers(const std::string& name, const std::vector<Eigen::Vector2d>& points,
                         const std::string& colour, Marker marker, double radius) {
  series_.push_back({Kind::kMarkers, name, colour, points, radius, false, marker});
}

void SvgPlot::addBands(const std::string& name, const std::vector<std::pair<double, double>>& spans,
                       const std::string& colour) {
  Series series{Kind::kBands, name, colour, {}, 0.0, false, Marker::kCircle};
  for (const auto& [x0, x1] : spans) series.points.emplace_back(x0, x1);
  series_.push_back(std::move(series));
}

void SvgPlot::addLabel(const Eigen::Vector2d& at, const std::string& text, const std::string& colour) {
  labels_.push_back({at, text, colour});
}

bool SvgPlot::hasData() const {
  for (const Series& series : series_) {
    for (const Eigen::Vector2d& p : series.points) {
      if (p.allFinite()) return true;
    }
  }
  return false;
}

SvgPlot::Layout SvgPlot::layout() const {
  Range x, y;
  for (const Series& series : series_) {
    for (const Eigen::Vector2d& p : series.points) {
      if (!p.allFinite()) continue;
      x.add(p.x());
      if (series.kind == Kind::kBands) x.add(p.y()); else y.add(p.y());
    }
  }
  if (!x.valid()) x = Range{0.0, 1.0};
  if (!y.valid()) y = Range{0.0, 1.0};
  if (y_from_zero_) y.lo = std::min(y.lo, 0.0);
  widen(&x);
  widen(&y);
  if (fixed_y_) {
    y = Range{y_lo_, y_hi_};
  } else {
    // Room above the highest value; none below a zero baseline.
    const double margin = 0.05 * y.span();
    y.hi += margin;
    if (!(y_from_zero_ && y.lo == 0.0)) y.lo -= margin;
  }
  Layout l;
  l.left = show_y_axis_ ? 64.0 : 14.0;
  l.right = width_ - 16.0;
  l.top = 30.0;
  l.bottom = height_ - 44.0;
  if (equal_aspect_) {
    pad(&x, 0.04);
    equalise(&x, &y, l.right - l.left, l.bottom - l.top);
  }
  l.x_lo = x.lo, l.x_hi = x.hi, l.y_lo = y.lo, l.y_hi = y.hi;
  const auto places = legendPlaces(l.left, height_ + kLegendTop);
  l.total_height = places.empty() ? height_ : static_cast<int>(places.back().second.y() + 12.0);
  return l;
}

std::string SvgPlot::renderAxes(const Layout& l) const {
  std::ostringstream grid, labels;
  const double x_step = niceStep(l.x_hi - l.x_lo, (l.right - l.left) / 90.0);
  for (const double v : ticks(l.x_lo, l.x_hi, x_step)) {
    const double x = l.pixel({v, l.y_lo}).x();
    grid << "M" << px(x) << "," << px(l.top) << "V" << px(l.bottom);
    labels << "<text class=\"tick\" x=\"" << px(x) << "\" y=\"" << px(l.bottom + 16)
           << "\" text-anchor=\"middle\">" << tickText(v, x_step) << "</text>";
  }
  if (show_y_axis_) {
    const double y_step = niceStep(l.y_hi - l.y_lo, (l.bottom - l.top) / 45.0);
    for (const double v : ticks(l.y_lo, l.y_hi, y_step)) {
      const double y = l.pixel({l.x_lo, v}).y();
      grid << "M" << px(l.left) << "," << px(y) << "H" << px(l.right);
      labels << "<text class=\"tick\" x=\"" << px(l.left - 6) << "\" y=\"" << px(y + 4)
             << "\" text-anchor=\"end\">" << tickText(v, y_step) << "</text>";
    }
    labels << "<text class=\"axis-label\" transform=\"translate(14," << px(0.5 * (l.top + l.bottom))
           << ") rotate(-90)\" text-anchor=\"middle\">" << escapeHtml(y_label_) << "</text>";
  }
  labels << "<text class=\"axis-label\" x=\"" << px(0.5 * (l.left + l.right)) << "\" y=\"" << px(l.bottom + 34)
         << "\" text-anchor=\"middle\">" << escapeHtml(x_label_) << "</text>";
  std::ostringstream out;
  out << "<path class=\"grid\" d=\"" << grid.str() << "\"/>\n"
      << "<path class=\"axis\" d=\"M" << px(l.left) << "," << px(l.top) << "V" << px(l.bottom) << "H"
      << px(l.right) << "\"/>\n"
      << labels.str() << "\n<text class=\"plot-title\" x=\"" << px(l.left) << "\" y=\"18\">" << escapeHtml(title_)
      << "</text>\n";
  return out.str();
}

std::string SvgPlot::renderSeries(const Series& s, const Layout& l) const {
  std::string d;
  if (s.kind == Kind::kLine) d = linePath(s.points, l);
  for (const Eigen::Vector2d& p : s.points) {
    if (!p.allFinite()) continue;
    if (s.kind == Kind::kMarkers) d += markerPath(l.pixel(p), s.marker, s.size);
    if (s.kind != Kind::kBands) continue;
    // A band is at least a pixel wide, so one lost frame in a long run still shows.
    const double x0 = l.pixel({std::min(p.x(), p.y()), 0}).x();
    const double x1 = std::max(l.pixel({std::max(p.x(), p.y()), 0}).x(), x0 + 1.0);
    d += "M" + px(x0) + "," + px(l.top) + "H" + px(x1) + "V" + px(l.bottom) + "H" + px(x0) + "Z";
  }
  if (d.empty()) return "";
  const bool stroked = s.kind == Kind::kLine || (s.kind == Kind::kMarkers && s.marker == Marker::kCross);
  const double width = s.kind == Kind::kLine ? s.size : 1.8;
  return "<path class=\"series\" data-name=\"" + escapeHtml(s.name) + "\" " +
         paint(s.colour, stroked, width, s.dashed) + " d=\"" + d + "\"/>\n";
}

std::string SvgPlot::renderLabels(const Layout& l) const {
  std::ostringstream out;
  for (const Label& label : labels_) {
    if (!label.at.allFinite()) continue;
    const Eigen::Vector2d p = l.pixel(label.at);
    out << "<text class=\"data-label\" x=\"" << px(p.x() + 6) << "\" y=\"" << px(p.y() - 6) << "\" fill=\""
        << escapeHtml(label.colour) << "\">" << escapeHtml(label.text) << "</text>\n";
  }
  return out.str();
}

std::vector<std::pair<const SvgPlot::Series*, Eigen::Vector2d>> SvgPlot::legendPlaces(double left,
                                                                                      double top) const {
  std::vector<std::pair<const Series*, Eigen::Vector2d>> places;
  std::set<std::string> named;
  Eigen::Vector2d next(left, top);
  for (const Series& series : series_) {
    if (series.name.empty() || !named.insert(series.name).second) continue;
    // No font metrics on the server: at most about 7.2 pixels per character of the 12 px labels.
    const double width = 36.0 + 7.2 * static_cast<double>(series.name.size());
    if (next.x() > left && next.x() + width > width_ - 8.0) next = {left, next.y() + kLegendRow};
    places.emplace_back(&series, next);
    next.x() += width;
  }
  return places;
}

std::string SvgPlot::renderLegend(const Layout& l) const {
  std::ostringstream out;
  out << "<g class=\"legend\">";
  for (const auto& [series, place] : legendPlaces(l.left, height_ + kLegendTop)) {
    const Eigen::Vector2d centre = place + Eigen::Vector2d(9, 0);
    std::string swatch;
    if (series->kind == Kind::kLine) {
      swatch = "<path " + paint(series->colour, true, std::max(series->size, 2.0), series->dashed) + " d=\"M" +
               at(place) + "h18\"/>";
    } else if (series->kind == Kind::kMarkers) {
      const bool stroked = series->marker == Marker::kCross;
      swatch = "<path " + paint(series->colour, stroked, 1.8, false) + " d=\"" +
               markerPath(centre, series->marker, 4.5) + "\"/>";
    } else {
      swatch = "<rect x=\"" + px(place.x()) + "\" y=\"" + px(place.y() - 6) + "\" width=\"18\" height=\"12\" " +
               paint(series->colour, false, 0, false) + "/>";
    }
    out << swatch << "<text class=\"legend-text\" x=\"" << px(place.x() + 24) << "\" y=\"" << px(place.y() + 4)
        << "\">" << escapeHtml(series->name) << "</text>";
  }
  out << "</g>\n";
  return out.str();
}

std::string SvgPlot::render() const {
  const Layout l = layout();
  std::ostringstream out;
  out << "<svg class=\"plot\" id=\"" << escapeHtml(id_) << "\" width=\"" << width_ << "\" height=\""
      << l.total_height << "\" viewBox=\"0 0 " << width_ << " " << l.total_height << "\" role=\"img\" aria-label=\""
      << escapeHtml(title_) << "\">\n<title>" << escapeHtml(title_) << "</title>\n";
  out << "<defs><clipPath id=\"" << escapeHtml(id_) << "-clip\"><rect x=\"" << px(l.left) << "\" y=\"" << px(l.top)
      << "\" width=\"" << px(l.right - l.left) << "\" height=\"" << px(l.bottom - l.top)
      << "\"/></clipPath></defs>\n";
  out << "<rect class=\"area\" x=\"" << px(l.left) << "\" y=\"" << px(l.top) << "\" width=\"" << px(l.right - l.left)
      << "\" height=\"" << px(l.bottom - l.top) << "\"/>\n";
  out << renderAxes(l) << "<g clip-path=\"url(#" << escapeHtml(id_) << "-clip)\">\n";
  // Bands under lines under markers, whatever order they were added in.
  for (const Kind kind : {Kind::kBands, Kind::kLine, Kind::kMarkers}) {
    for (const Series& series : series_) {
      if (series.kind == kind) out << renderSeries(series, l);
    }
  }
  out << "</g>\n" << renderLabels(l) << renderLegend(l) << "</svg>\n";
  return out.str();
}

}  // namespace report
}  // namespace pf2
