#include "pf2/registration/reference_cleaner.h"

#include <algorithm>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

// Each pixel's smallest depth over its 3x3 neighbourhood, holes (0) ignored; a hole with no
// depth around stays 0. `filled` is a working image (reused between calls).
void nearestDepth(const cv::Mat& depth, cv::Mat* filled, cv::Mat* nearest) {
  const float none = std::numeric_limits<float>::max();
  depth.copyTo(*filled);
  filled->setTo(none, depth <= 0.0f);
  cv::erode(*filled, *nearest, cv::Mat());
  nearest->setTo(0.0f, *nearest == none);
}

// Removes full-resolution pixel block (u, v, size) from every level's depth.
void removeBlock(OdometryFrame* frame, int u, int v, int size) {
  for (size_t l = 0; l < frame->levels.size(); ++l) {
    cv::Mat& depth = frame->levels[l].depth;
    const int s = 1 << l;
    const cv::Rect block = cv::Rect(u / s, v / s, std::max(1, size / s), std::max(1, size / s)) &
                           cv::Rect(0, 0, depth.cols, depth.rows);
    depth(block).setTo(0.0f);
  }
}

}  // namespace

ReferenceCleaner::ReferenceCleaner(const Options& options) : options_(options) {
  if (options_.votes < 1 || options_.votes > 255) throw Error("ReferenceCleaner: votes must be in [1, 255]");
  if (options_.stride < 1 || options_.stride > 16) throw Error("ReferenceCleaner: stride must be in [1, 16]");
  if (!(options_.margin >= 0.0) || !(options_.relative_margin >= 0.0))
    throw Error("ReferenceCleaner: margins must be >= 0");
}

void ReferenceCleaner::reset() { votes_.release(); }

int ReferenceCleaner::update(OdometryFrame* reference, const OdometryFrame& current,
                             const Eigen::Isometry3d& T_ref_cur) {
  if (!options_.enabled || reference->levels.empty() || current.levels.empty()) return 0;
  const OdometryLevel& ref = reference->levels[0];
  const OdometryLevel& cur = current.levels[0];
  const int stride = options_.stride;
  const cv::Size grid((ref.depth.cols + stride - 1) / stride, (ref.depth.rows + stride - 1) / stride);
  if (votes_.size() != grid) votes_ = cv::Mat::zeros(grid, CV_8U);
  nearestDepth(cur.depth, &filled_cur_, &nearest_cur_);

  const Eigen::Isometry3f T_cur_ref = T_ref_cur.inverse().cast<float>();
  const CameraIntrinsics& kr = ref.intrinsics;
  const CameraIntrinsics& kc = cur.intrinsics;
  int removed = 0;
  for (int gv = 0; gv < grid.height; ++gv) {
    const int v = gv * stride;
    const float* z_row = ref.depth.ptr<float>(v);
    uint8_t* votes = votes_.ptr<uint8_t>(gv);
    for (int gu = 0; gu < grid.width; ++gu) {
      const int u = gu * stride;
      const float z = z_row[u];
      if (!(z > 0.0f)) continue;
      const Eigen::Vector3f p_ref((u - kr.cx) * z / kr.fx, (v - kr.cy) * z / kr.fy, z);
      const Eigen::Vector3f p_cur = T_cur_ref * p_ref;
      if (!(p_cur.z() > 0.0f)) continue;
      const int uc = static_cast<int>(kc.fx * p_cur.x() / p_cur.z() + kc.cx + 0.5f);
      const int vc = static_cast<int>(kc.fy * p_cur.y() / p_cur.z() + kc.cy + 0.5f);
      if (uc < 0 || vc < 0 || uc >= nearest_cur_.cols || vc >= nearest_cur_.rows) continue;
      const float behind = nearest_cur_.at<float>(vc, uc);
      const float margin = static_cast<float>(options_.margin + options_.relative_margin * p_cur.z());
      if (!(behind > p_cur.z() + margin)) continue;
      if (++votes[gu] < options_.votes) continue;
      removeBlock(reference, u, v, stride);
      ++removed;
    }
  }
  return removed;
}

}  // namespace pf2
