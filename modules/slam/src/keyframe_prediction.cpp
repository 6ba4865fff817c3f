#include "pf2/slam/keyframe_prediction.h"

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"
#include "pf2/filters/dual_bbox_filter.h"

namespace pf2 {

KeyframeDepthPrediction::KeyframeDepthPrediction(const Options& options) : options_(options) {
  if (options_.keyframes < 1) throw Error("KeyframeDepthPrediction: keyframes must be >= 1");
  if (options_.downsample < 1 || options_.downsample > 8)
    throw Error("KeyframeDepthPrediction: downsample must be in [1, 8]");
}

const cv::Mat& KeyframeDepthPrediction::depthOf(const Keyframe& keyframe) {
  auto found = depth_by_id_.find(keyframe.id);
  if (found != depth_by_id_.end()) return found->second;
  cv::Mat metres;
  keyframe.depth.convertTo(metres, CV_32F, 1.0 / Keyframe::kDepthUnitsPerMetre);
  if (options_.downsample > 1) {
    // Nearest neighbour: averaging depth across an edge would invent surfaces.
    cv::resize(metres, metres, cv::Size(), 1.0 / options_.downsample, 1.0 / options_.downsample,
               cv::INTER_NEAREST);
  }
  // Only the newest keyframes are ever asked for: older conversions are dropped.
  while (static_cast<int>(depth_by_id_.size()) > options_.keyframes) depth_by_id_.erase(depth_by_id_.begin());
  return depth_by_id_.emplace(keyframe.id, metres).first->second;
}

cv::Mat KeyframeDepthPrediction::predict(const KeyframeMap& map, const Eigen::Isometry3d& T_w_c,
                                         const CameraIntrinsics& intrinsics) {
  const std::map<int, Eigen::Isometry3d> poses = map.poses();
  if (poses.empty()) return cv::Mat();
  const CameraIntrinsics small = intrinsics.scaled(1.0 / options_.downsample);
  cv::Mat farthest;
  int used = 0;
  for (auto it = poses.rbegin(); it != poses.rend() && used < options_.keyframes; ++it, ++used) {
    const std::shared_ptr<const Keyframe> keyframe = map.keyframe(it->first);
    if (!keyframe || keyframe->depth.empty()) continue;
    const cv::Mat warped = warpDepth(depthOf(*keyframe), small, T_w_c.inverse() * it->second);
    if (farthest.empty()) farthest = warped;
    else cv::max(farthest, warped, farthest);
  }
  if (farthest.empty()) return cv::Mat();
  cv::Mat full;
  cv::resize(farthest, full, cv::Size(intrinsics.width, intrinsics.height), 0, 0, cv::INTER_NEAREST);
  return options_.distortion.empty() ? full : distort(full, intrinsics);
}

cv::Mat KeyframeDepthPrediction::distort(const cv::Mat& rectified, const CameraIntrinsics& k) {
  const CameraIntrinsics& m = map_intrinsics_;
  if (rectified_of_pixel_.size() != rectified.size() || m.fx != k.fx || m.fy != k.fy || m.cx != k.cx ||
      m.cy != k.cy) {
    std::vector<cv::Point2f> pixels;
    pixels.reserve(rectified.total());
    for (int v = 0; v < rectified.rows; ++v)
      for (int u = 0; u < rectified.cols; ++u) pixels.emplace_back(static_cast<float>(u), static_cast<float>(v));
    const cv::Matx33d K(k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
    std::vector<cv::Point2f> positions;
    cv::undistortPoints(pixels, positions, K, options_.distortion, cv::noArray(), K);
    rectified_of_pixel_ = cv::Mat(positions, true).reshape(2, rectified.rows);
    map_intrinsics_ = k;
  }
  cv::Mat out;
  cv::remap(rectified, out, rectified_of_pixel_, cv::noArray(), cv::INTER_NEAREST, cv::BORDER_CONSTANT, 0);
  return out;
}

}  // namespace pf2
