#include "pf2/eval/trajectory_plot.h"

#include <algorithm>
#include <cstdio>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"

namespace pf2 {

namespace {

constexpr int kSize = 800;    // image side, pixels
constexpr int kMargin = 40;   // blank border, pixels

// Maps world points to image pixels on the plane of the two axes with the largest spread.
struct TopView {
  int axis_u = 0, axis_v = 1;
  double scale = 1.0;
  Eigen::Vector2d origin = Eigen::Vector2d::Zero();

  explicit TopView(const AteResult& ate) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
    for (const auto* points : {&ate.ground_truth, &ate.aligned_estimate}) {
      for (const Eigen::Vector3d& p : *points) {
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
    }
    const Eigen::Vector3d extent = hi - lo;
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int a, int b) { return extent[a] > extent[b]; });
    axis_u = std::min(order[0], order[1]);
    axis_v = std::max(order[0], order[1]);
    const double span = std::max({extent[axis_u], extent[axis_v], 1e-6});
    scale = (kSize - 2 * kMargin) / span;
    origin = {lo[axis_u], lo[axis_v]};
  }
  cv::Point2d pixel(const Eigen::Vector3d& p) const {
    // Image rows grow downwards: flip v so the plot reads like a map.
    return {kMargin + (p[axis_u] - origin.x()) * scale,
            kSize - kMargin - (p[axis_v] - origin.y()) * scale};
  }
};

const char* axisName(int axis) { return axis == 0 ? "x" : axis == 1 ? "y" : "z"; }

std::string lowerExtension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
  return ext;
}

std::string caption(const AteResult& ate, const TopView& view) {
  char text[160];
  std::snprintf(text, sizeof(text), "ATE RMSE %.4f m over %d poses; plane %s-%s", ate.translation.rmse,
                ate.translation.count, axisName(view.axis_u), axisName(view.axis_v));
  return text;
}

void writePng(const AteResult& ate, const TopView& view, const std::string& path) {
  cv::Mat image(kSize, kSize, CV_8UC3, cv::Scalar(255, 255, 255));
  const auto draw_path = [&](const std::vector<Eigen::Vector3d>& points, const cv::Scalar& colour) {
    for (size_t k = 1; k < points.size(); ++k) {
      cv::line(image, view.pixel(points[k - 1]), view.pixel(points[k]), colour, 2, cv::LINE_AA);
    }
  };
  for (size_t k = 0; k < ate.ground_truth.size(); ++k) {
    cv::line(image, view.pixel(ate.ground_truth[k]), view.pixel(ate.aligned_estimate[k]),
             cv::Scalar(0, 0, 230), 1, cv::LINE_AA);
  }
  draw_path(ate.ground_truth, cv::Scalar(0, 0, 0));
  draw_path(ate.aligned_estimate, cv::Scalar(200, 90, 0));
  cv::putText(image, caption(ate, view), {10, 22}, cv::FONT_HERSHEY_SIMPLEX, 0.55, {0, 0, 0}, 1,
              cv::LINE_AA);
  cv::putText(image, "black: ground truth   blue: estimate   red: error", {10, kSize - 12},
              cv::FONT_HERSHEY_SIMPLEX, 0.5, {0, 0, 0}, 1, cv::LINE_AA);
  std::vector<uchar> encoded;
  if (!cv::imencode(".png", image, encoded)) throw fileError(path, "PNG encoding failed");
  writeFileAtomically(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(encoded.data()), encoded.size());
  });
}

void writeSvg(const AteResult& ate, const TopView& view, const std::string& path) {
  const auto polyline = [&](const std::vector<Eigen::Vector3d>& points, const char* colour) {
    std::ostringstream out;
    out << "<polyline fill=\"none\" stroke-width=\"2\" stroke=\"" << colour << "\" points=\"";
    for (const Eigen::Vector3d& p : points) {
      const cv::Point2d px = view.pixel(p);
      out << px.x << "," << px.y << " ";
    }
    out << "\"/>\n";
    return out.str();
  };
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kSize << "\" height=\"" << kSize
        << "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    out << "<g stroke=\"#e00000\" stroke-width=\"1\">\n";
    for (size_t k = 0; k < ate.ground_truth.size(); ++k) {
      const cv::Point2d a = view.pixel(ate.ground_truth[k]);
      const cv::Point2d b = view.pixel(ate.aligned_estimate[k]);
      out << "<line x1=\"" << a.x << "\" y1=\"" << a.y << "\" x2=\"" << b.x << "\" y2=\"" << b.y
          << "\"/>\n";
    }
    out << "</g>\n" << polyline(ate.ground_truth, "black") << polyline(ate.aligned_estimate, "#005ac8");
    out << "<text x=\"10\" y=\"22\" font-family=\"sans-serif\" font-size=\"15\">" << caption(ate, view)
        << "</text>\n<text x=\"10\" y=\"" << kSize - 12
        << "\" font-family=\"sans-serif\" font-size=\"13\">black: ground truth, blue: estimate, "
           "red: error</text>\n</svg>\n";
  });
}

}  // namespace

void plotTrajectories(const AteResult& ate, const std::string& path) {
  const TopView view(ate);
  const std::string ext = lowerExtension(path);
  if (ext == "png") {
    writePng(ate, view, path);
  } else if (ext == "svg") {
    writeSvg(ate, view, path);
  } else {
    throw fileError(path, "plot format must be .png or .svg");
  }
}

}  // namespace pf2
