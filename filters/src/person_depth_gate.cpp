#include "pf2/filters/person_depth_gate.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

namespace pf2 {
namespace {

constexpr float kNoCore = 1e9f;  // nearest-depth image where no core pixel lies in the window

// The area whose pixels can have core depths within `radius`: the core's bounds grown by it,
// clipped to the image, its corner on even coordinates so that 2x2 blocks line up with it.
cv::Rect gatedArea(const cv::Rect& core_bounds, int radius, const cv::Size& image) {
  cv::Rect area = (core_bounds + cv::Point(-radius, -radius) + cv::Size(2 * radius, 2 * radius)) &
                  cv::Rect(cv::Point(0, 0), image);
  const int x = area.x & ~1, y = area.y & ~1;
  return cv::Rect(x, y, area.br().x - x, area.br().y - y);
}

}  // namespace

// The nearest / farthest core depth of each 2x2 block of `area` (half resolution).
void PersonDepthGate::blockExtremes(const cv::Mat& depth, const cv::Mat& core) {
  const cv::Size half((depth.cols + 1) / 2, (depth.rows + 1) / 2);
  nearest_.create(half, CV_32F);
  farthest_.create(half, CV_32F);
  nearest_.setTo(kNoCore);
  farthest_.setTo(0);
  for (int v = 0; v < depth.rows; ++v) {
    const float* z = depth.ptr<float>(v);
    const uint8_t* c = core.ptr<uint8_t>(v);
    float* lo = nearest_.ptr<float>(v / 2);
    float* hi = farthest_.ptr<float>(v / 2);
    for (int u = 0; u < depth.cols; ++u) {
      if (!c[u] || !(z[u] > 0.f)) continue;
      lo[u / 2] = std::min(lo[u / 2], z[u]);
      hi[u / 2] = std::max(hi[u / 2], z[u]);
    }
  }
}

cv::Mat PersonDepthGate::outsidePeople(const cv::Mat& depth, const cv::Mat& core) {
  if (options_.radius <= 0) return cv::Mat();
  const cv::Rect bounds = cv::boundingRect(core);
  if (bounds.empty()) return cv::Mat();
  const cv::Rect area = gatedArea(bounds, options_.radius, depth.size());
  const cv::Mat d = depth(area);
  blockExtremes(d, core(area));
  // The window's minimum and maximum at half resolution (a quarter of the pixels, half the window):
  // a person's depth varies slowly next to the margin, and this is the gate's main cost.
  const int r = (options_.radius + 1) / 2;
  const cv::Mat window = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * r + 1, 2 * r + 1));
  cv::erode(nearest_, nearest_, window, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(kNoCore));
  cv::dilate(farthest_, farthest_, window, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  cv::Mat outside = cv::Mat::zeros(depth.size(), CV_8U);
  const float margin = static_cast<float>(options_.margin);
  for (int v = 0; v < area.height; ++v) {
    const float* z = d.ptr<float>(v);
    const float* lo = nearest_.ptr<float>(v / 2);
    const float* hi = farthest_.ptr<float>(v / 2);
    uint8_t* out = outside.ptr<uint8_t>(v + area.y) + area.x;
    for (int u = 0; u < area.width; ++u) {
      const bool has_core = hi[u / 2] > 0.f;
      const bool apart = (z[u] < lo[u / 2] - margin) | (z[u] > hi[u / 2] + margin);
      out[u] = static_cast<uint8_t>(-static_cast<int>(has_core & apart & (z[u] > 0.f)));
    }
  }
  return outside;
}

}  // namespace pf2
