#include "pf2/surface/up_direction.h"

#include <cmath>
#include <vector>

#include "pf2/core/error.h"

namespace pf2 {

namespace {

// The unit normals of the surface at every stride-th pixel, camera frame, facing the camera;
// pixels without depth, beyond max_depth or next to a depth step give none.
std::vector<Eigen::Vector3d> surfaceNormals(const cv::Mat& depth, const CameraIntrinsics& K,
                                            const UpDirectionEstimator::Options& o) {
  std::vector<Eigen::Vector3d> normals;
  const int s = o.stride_px;
  const auto usable = [&](float z, float z0) {
    return std::isfinite(z) && z > 0 && z <= o.max_depth && std::abs(z - z0) <= o.max_depth_step * z0;
  };
  for (int v = 0; v + s < depth.rows; v += s) {
    const float* row = depth.ptr<float>(v);
    const float* below = depth.ptr<float>(v + s);
    for (int u = 0; u + s < depth.cols; u += s) {
      const float z = row[u];
      if (!usable(z, z) || !usable(row[u + s], z) || !usable(below[u], z)) continue;
      const Eigen::Vector3d p = K.backProject(u, v, z);
      Eigen::Vector3d n = (K.backProject(u + s, v, row[u + s]) - p).cross(K.backProject(u, v + s, below[u]) - p);
      const double length = n.norm();
      if (!(length > 0)) continue;
      n /= length;
      normals.push_back(n.dot(p) > 0 ? Eigen::Vector3d(-n) : n);
    }
  }
  return normals;
}

// The mean direction of the normals within `angle` of `around` (zero when there are none), and
// their count in *count.
Eigen::Vector3d meanWithin(const std::vector<Eigen::Vector3d>& normals_w, const Eigen::Vector3d& around,
                           double angle, int* count) {
  const double min_cos = std::cos(angle);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  *count = 0;
  for (const Eigen::Vector3d& n : normals_w) {
    if (n.dot(around) < min_cos) continue;
    sum += n;
    ++*count;
  }
  return sum;
}

}  // namespace

UpDirectionEstimator::UpDirectionEstimator(const Options& options, const Eigen::Vector3d& fallback_w)
    : options_(options), fallback_w_(fallback_w) {
  const bool ok = options.stride_px >= 1 && options.stride_px <= 64 && options.max_depth > 0 &&
                  options.max_depth <= 100 && options.max_depth_step > 0 && options.max_depth_step <= 1 &&
                  options.max_angle > 0 && options.max_angle < M_PI / 2 && options.fine_angle > 0 &&
                  options.fine_angle <= options.max_angle && options.min_frame_normals >= 1 &&
                  options.settled_normals >= 1;
  if (!ok) {
    throw Error(
        "UpDirectionEstimator: an option is out of range (stride_px [1, 64], max_depth (0, 100] m, "
        "max_depth_step (0, 1], max_angle (0, pi/2) rad, fine_angle (0, max_angle], normals counts >= 1)");
  }
  if (!(fallback_w.allFinite() && fallback_w.norm() > 0)) throw Error("UpDirectionEstimator: the fallback up is zero");
  fallback_w_.normalize();
}

bool UpDirectionEstimator::update(const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                                  const Eigen::Isometry3d& T_w_c) {
  if (settled() || depth.empty()) return false;
  if (depth.type() != CV_32FC1) throw Error("UpDirectionEstimator::update: depth must be CV_32F (metres)");
  std::vector<Eigen::Vector3d> normals_w = surfaceNormals(depth, intrinsics, options_);
  for (Eigen::Vector3d& n : normals_w) n = T_w_c.linear() * n;
  // Wide, then narrow twice: the floor's and table tops' normals, not a wall's or a slope's.
  int count = 0;
  Eigen::Vector3d mean = meanWithin(normals_w, up_w(), options_.max_angle, &count);
  for (int pass = 0; pass < 2 && count > 0; ++pass) {
    mean = meanWithin(normals_w, mean.normalized(), options_.fine_angle, &count);
  }
  if (count < options_.min_frame_normals) return false;
  sum_w_ += mean;
  normals_ += count;
  return true;
}

Eigen::Vector3d UpDirectionEstimator::up_w() const {
  return normals_ > 0 ? Eigen::Vector3d(sum_w_.normalized()) : fallback_w_;
}

}  // namespace pf2
