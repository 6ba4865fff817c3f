#include "pf2/slam/removal_backfill.h"

#include <cmath>
#include <string>

#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"

namespace pf2 {

namespace {

// Moved points land about one every kStride pixels; a disc of this radius closes the gaps between
// them (an estimate on pf2_synth with every second pixel: 1 px left a tenth of the gain).
constexpr int kHitDilation = 2;
// A waiting frame where no more than this share of the points in its view meet its depth or its
// removed pixels did not have the people there; after kIdleFrames such frames in a row the older
// ones are not tried.
constexpr double kMinHitShare = 0.02;
constexpr int kIdleFrames = 2;
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
    // Newest first; once two frames in a row had (next to) none of the people where they are now
    // (neither removed nor measured there), the people have moved since and the older frames would
    // take nothing either.
    int idle = 0;
    for (auto it = waiting_.rbegin(); it != waiting_.rend() && idle < kIdleFrames; ++it) {
      idle = carryInto(people_w, &*it) ? 0 : idle + 1;
    }
  }
  ++pushed_;
  waiting_.push_back({std::move(frame), cv::Mat()});
  while (waiting_.size() > static_cast<size_t>(options_.frames)) {
    release(&waiting_.front());
    waiting_.pop_front();
  }
}

bool RemovalBackfill::carriesNext() const { return options_.frames > 0 && pushed_ % kCarryEvery == 0; }

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

bool RemovalBackfill::carryInto(const Points& people_w, Waiting* waiting) const {
  const Frame& frame = waiting->frame;
  if (!frame.T_w_c) return false;
  // One 3x4 product per point: rows 0-1 give the pixel times the depth, row 2 the depth.
  const CameraIntrinsics& k = frame.intrinsics;
  Eigen::Matrix3f K;
  K << static_cast<float>(k.fx), 0.f, static_cast<float>(k.cx), 0.f, static_cast<float>(k.fy),
      static_cast<float>(k.cy), 0.f, 0.f, 1.f;
  const Eigen::Isometry3f T_c_w = frame.T_w_c->inverse().cast<float>();
  const Eigen::Matrix3f A = K * T_c_w.linear();
  const Eigen::Vector3f b = K * T_c_w.translation();
  const float tolerance = static_cast<float>(options_.tolerance);
  const float max_u = static_cast<float>(frame.depth.cols) - 0.5f, max_v = static_cast<float>(frame.depth.rows) - 0.5f;
  size_t in_view = 0, met = 0;
  for (const Eigen::Vector3f& p_w : people_w) {
    const Eigen::Vector3f q = A * p_w + b;
    const float z = q.z();
    if (z < kMinDepth) continue;
    const float u = q.x() / z, v = q.y() / z;
    if (!(u >= -0.5f && v >= -0.5f && u < max_u && v < max_v)) continue;
    const int iu = static_cast<int>(u + 0.5f), iv = static_cast<int>(v + 0.5f);  // nearest pixel
    ++in_view;
    if (frame.removed.ptr<uint8_t>(iv)[iu]) {  // removed already: the person was there, found then
      ++met;
      continue;
    }
    const float d = frame.depth.ptr<float>(iv)[iu];
    if (!(d > 0.f) || std::abs(d - z) >= tolerance + 0.01f * z) continue;
    if (waiting->hits.empty()) waiting->hits = cv::Mat::zeros(frame.depth.size(), CV_8U);
    waiting->hits.ptr<uint8_t>(iv)[iu] = 255;
    ++met;
  }
  return met > kMinHitShare * in_view;
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
