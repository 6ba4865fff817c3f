#include "pf2/slam/removal_backfill.h"

#include <cmath>
#include <string>

#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"

namespace pf2 {

namespace {

// Moved points land one every `stride` pixels at most; a disc of this radius closes the gaps
// between them (pf2_synth, stride 2: 1 px left a tenth of the gain, 2 px cost 0.1 point of the
// static depth).
constexpr int kHitDilation = 2;
// Points closer to a waiting camera than this are behind or at its lens.
constexpr float kMinDepth = 0.1f;

void check(bool ok, const std::string& key, const std::string& range) {
  if (!ok) throw Error("RemovalBackfill: " + key + " must lie in " + range);
}

}  // namespace

RemovalBackfill::RemovalBackfill(const Options& options) : options_(options) {
  check(options.frames >= 0 && options.frames <= 300, "frames", "[0, 300]");
  check(options.tolerance >= 0.005 && options.tolerance <= 0.5, "tolerance", "[0.005, 0.5] m");
  check(options.floor_clearance >= 0.0 && options.floor_clearance <= 1.0, "floor_clearance", "[0, 1] m");
}

void RemovalBackfill::push(Frame frame, const Points& people_w) {
  if (frame.depth.type() != CV_32F || frame.removed.type() != CV_8U || frame.depth.size() != frame.removed.size()) {
    throw Error("RemovalBackfill::push: depth must be CV_32F and removed CV_8U of the same size");
  }
  if (!people_w.empty()) {
    for (Waiting& waiting : waiting_) carryInto(people_w, &waiting);
  }
  waiting_.push_back({std::move(frame), cv::Mat()});
  while (waiting_.size() > static_cast<size_t>(options_.frames)) {
    release(&waiting_.front());
    waiting_.pop_front();
  }
}

void RemovalBackfill::flush() {
  while (!waiting_.empty()) {
    release(&waiting_.front());
    waiting_.pop_front();
  }
}

RemovalBackfill::Points RemovalBackfill::personPoints(
    const cv::Mat& depth, const CameraIntrinsics& k, const Eigen::Isometry3d& T_w_c,
    const std::optional<std::pair<Eigen::Vector3d, double>>& floor, int stride) const {
  Points points;
  const Eigen::Isometry3f T = T_w_c.cast<float>();
  for (int v = 0; v < depth.rows; v += stride) {
    const float* d = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; u += stride) {
      if (!(d[u] > 0.f)) continue;
      const float z = d[u];
      const Eigen::Vector3f p_w = T * Eigen::Vector3f(static_cast<float>((u - k.cx) / k.fx) * z,
                                                      static_cast<float>((v - k.cy) / k.fy) * z, z);
      if (floor && floor->first.cast<float>().dot(p_w) - floor->second < options_.floor_clearance) continue;
      points.push_back(p_w);
    }
  }
  return points;
}

void RemovalBackfill::carryInto(const Points& people_w, Waiting* waiting) const {
  const Frame& frame = waiting->frame;
  if (!frame.T_w_c) return;
  const Eigen::Isometry3f T_c_w = frame.T_w_c->inverse().cast<float>();
  const CameraIntrinsics& k = frame.intrinsics;
  const float tolerance = static_cast<float>(options_.tolerance);
  for (const Eigen::Vector3f& p_w : people_w) {
    const Eigen::Vector3f p = T_c_w * p_w;
    if (p.z() < kMinDepth) continue;
    const int u = static_cast<int>(std::lround(k.fx * p.x() / p.z() + k.cx));
    const int v = static_cast<int>(std::lround(k.fy * p.y() / p.z() + k.cy));
    if (u < 0 || v < 0 || u >= frame.depth.cols || v >= frame.depth.rows) continue;
    const float d = frame.depth.at<float>(v, u);
    if (!(d > 0.f) || std::abs(d - p.z()) >= tolerance + 0.01f * p.z()) continue;
    if (waiting->hits.empty()) waiting->hits = cv::Mat::zeros(frame.depth.size(), CV_8U);
    waiting->hits.at<uint8_t>(v, u) = 255;
  }
}

void RemovalBackfill::release(Waiting* waiting) const {
  Frame& frame = waiting->frame;
  if (!waiting->hits.empty()) {
    const int size = 2 * kHitDilation + 1;
    cv::dilate(waiting->hits, waiting->hits, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size, size)));
    waiting->hits &= (frame.depth > 0.f);
    frame.depth.setTo(0.f, waiting->hits);
    frame.removed.setTo(255, waiting->hits);
  }
  if (frame.release) frame.release(frame);
}

}  // namespace pf2
