#include "pf2/surface/floor_height.h"

#include <cmath>

#include "pf2/core/error.h"

namespace pf2 {

FloorEstimator::FloorEstimator(const Options& options) : options_(options) {
  const Options& o = options;
  const bool ok = o.stride_px >= 1 && o.stride_px <= 64 && o.max_depth > 0 && o.max_depth <= 100 && o.bin_size > 0 &&
                  o.bin_size <= 0.5 && o.range > 0 && o.range <= 50 && o.min_share > 0 && o.min_share <= 1 &&
                  o.min_points >= 1 && o.settled_points >= o.min_points;
  if (!ok) {
    throw Error(
        "FloorEstimator: an option is out of range (stride_px [1, 64], max_depth (0, 100] m, bin_size (0, 0.5] m, "
        "range (0, 50] m, min_share (0, 1], min_points >= 1, settled_points >= min_points)");
  }
  bins_.assign(static_cast<size_t>(std::ceil(2 * o.range / o.bin_size)), 0);
}

namespace {

// Whether the surface from p to the neighbouring pixel (u, v) at depth z runs level (a wall's or a
// person's does not): no depth step between them, and a rise of at most a quarter of the step
// (14 degrees).
bool horizontalAt(const Eigen::Vector3d& p, const CameraIntrinsics& intrinsics, int u, int v, float z,
                  const Eigen::Vector3d& up_c) {
  if (!(z > 0.f) || std::abs(z - p.z()) > 0.05 * p.z()) return false;
  const Eigen::Vector3d step = intrinsics.backProject(u, v, z) - p;
  return std::abs(up_c.dot(step)) <= 0.25 * step.norm();
}

}  // namespace

void FloorEstimator::update(const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                            const Eigen::Isometry3d& T_w_c, const Eigen::Vector3d& up_w) {
  if (points_ >= options_.settled_points || depth.empty()) return;
  if (depth.type() != CV_32FC1) throw Error("FloorEstimator::update: depth must be CV_32F (metres)");
  // The height of camera point p: up_w . (R p + t) = (R^T up_w) . p + up_w . t.
  const Eigen::Vector3d up_c = T_w_c.linear().transpose() * up_w;
  const double camera_height = up_w.dot(T_w_c.translation());
  const int s = options_.stride_px;
  for (int v = 0; v + s < depth.rows; v += s) {
    const float* row = depth.ptr<float>(v);
    const float* below = depth.ptr<float>(v + s);
    for (int u = 0; u + s < depth.cols; u += s) {
      const float z = row[u];
      if (!(z > 0.f && z <= options_.max_depth)) continue;
      const Eigen::Vector3d p = intrinsics.backProject(u, v, z);
      if (!horizontalAt(p, intrinsics, u + s, v, row[u + s], up_c) ||
          !horizontalAt(p, intrinsics, u, v + s, below[u], up_c)) {
        continue;
      }
      const double bin = std::floor((up_c.dot(p) + camera_height + options_.range) / options_.bin_size);
      if (bin < 0 || bin >= static_cast<double>(bins_.size())) continue;
      ++bins_[static_cast<size_t>(bin)];
      ++points_;
    }
  }
  locate();
}

// Points within one bin of bin i (the floor's noise and a slightly wrong up spread it over a few).
long FloorEstimator::window(size_t i) const {
  long count = bins_[i];
  if (i > 0) count += bins_[i - 1];
  if (i + 1 < bins_.size()) count += bins_[i + 1];
  return count;
}

void FloorEstimator::locate() {
  found_ = false;
  if (points_ < options_.min_points) return;
  const double min_count = options_.min_share * static_cast<double>(points_);
  size_t i = 0;
  while (i < bins_.size() && static_cast<double>(window(i)) < min_count) ++i;
  if (i == bins_.size()) return;
  // From the lowest dense window up to the top of its pile, then the mean height around it.
  while (i + 1 < bins_.size() && window(i + 1) > window(i)) ++i;
  double sum = 0, weight = 0;
  for (size_t j = i > 1 ? i - 2 : 0; j <= i + 2 && j < bins_.size(); ++j) {
    sum += static_cast<double>(bins_[j]) * ((static_cast<double>(j) + 0.5) * options_.bin_size - options_.range);
    weight += static_cast<double>(bins_[j]);
  }
  height_ = sum / weight;
  found_ = true;
}

}  // namespace pf2
