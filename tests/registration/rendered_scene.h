#pragma once
// Test fixture: ray-casts a textured box-shaped room (and a textured block standing in it) into
// exact RGB-D frames from any camera pose, so odometry can be checked against a known motion.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/frame.h"

namespace pf2 {
namespace test {

// Smooth value noise in [0, 1] on a plane, two octaves; `seed` separates the surfaces.
inline double valueNoise(double x, double y, uint32_t seed) {
  auto hash = [seed](int64_t i, int64_t j) {
    uint64_t h = static_cast<uint64_t>(i) * 0x9E3779B97F4A7C15ull ^
                 static_cast<uint64_t>(j) * 0xC2B2AE3D27D4EB4Full ^ (uint64_t(seed) << 32);
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 32;
    return static_cast<double>(h & 0xFFFF) / 65535.0;
  };
  auto octave = [&](double cell) {
    const double fx = x / cell, fy = y / cell;
    const int64_t i = static_cast<int64_t>(std::floor(fx)), j = static_cast<int64_t>(std::floor(fy));
    double a = fx - i, b = fy - j;
    a = a * a * (3 - 2 * a);
    b = b * b * (3 - 2 * b);
    return (1 - b) * ((1 - a) * hash(i, j) + a * hash(i + 1, j)) +
           b * ((1 - a) * hash(i, j + 1) + a * hash(i + 1, j + 1));
  };
  return 0.6 * octave(0.08) + 0.4 * octave(0.3);
}

// Room: x in [-2, 2], y in [-1.5, 1.2] (y down: floor at +1.2), z in [-2, 3.5]; a block
// x in [-0.6, 0.2], y in [0.4, 1.2], z in [1.6, 2.2] stands on the floor.
inline Frame renderRoom(const Eigen::Isometry3d& T_w_c, const CameraIntrinsics& k,
                        int index = 0) {
  Frame frame;
  frame.intrinsics = k;
  frame.index = index;
  frame.timestamp = index / 30.0;
  frame.rgb = cv::Mat(k.height, k.width, CV_8UC3);
  frame.depth = cv::Mat(k.height, k.width, CV_32F, cv::Scalar(0));
  const Eigen::Matrix3d R = T_w_c.rotation();
  const Eigen::Vector3d o = T_w_c.translation();
  const Eigen::Vector3d lo_room(-2.0, -1.5, -2.0), hi_room(2.0, 1.2, 3.5);
  const Eigen::Vector3d lo_box(-0.6, 0.4, 1.6), hi_box(0.2, 1.2, 2.2);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const Eigen::Vector3d d_c((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      const Eigen::Vector3d d = R * d_c;
      double best = 1e9;
      int axis = -1;
      uint32_t seed = 0;
      // Room walls seen from inside: the exit distance per axis.
      for (int a = 0; a < 3; ++a) {
        if (std::fabs(d[a]) < 1e-12) continue;
        const double t = ((d[a] > 0 ? hi_room[a] : lo_room[a]) - o[a]) / d[a];
        if (t > 0 && t < best) {
          best = t;
          axis = a;
          seed = 1 + a * 2 + (d[a] > 0);
        }
      }
      // Block seen from outside: slab entry.
      double t_in = -1e9, t_out = 1e9;
      int in_axis = -1;
      for (int a = 0; a < 3; ++a) {
        if (std::fabs(d[a]) < 1e-12) {
          if (o[a] < lo_box[a] || o[a] > hi_box[a]) t_in = 1e9;
          continue;
        }
        double t0 = (lo_box[a] - o[a]) / d[a], t1 = (hi_box[a] - o[a]) / d[a];
        if (t0 > t1) std::swap(t0, t1);
        if (t0 > t_in) {
          t_in = t0;
          in_axis = a;
        }
        t_out = std::min(t_out, t1);
      }
      if (in_axis >= 0 && t_in > 0 && t_in <= t_out && t_in < best) {
        best = t_in;
        axis = in_axis;
        seed = 11 + in_axis;
      }
      const Eigen::Vector3d p = o + best * d;
      const int a1 = (axis + 1) % 3, a2 = (axis + 2) % 3;
      const double g = valueNoise(p[a1], p[a2], seed);
      const double shade = 0.75 + 0.25 * std::fabs(d.normalized()[axis]);
      const double value = (30.0 + 200.0 * g) * shade;
      frame.rgb.at<cv::Vec3b>(v, u) = cv::Vec3b(cv::saturate_cast<uchar>(value * 0.9),
                                                 cv::saturate_cast<uchar>(value),
                                                 cv::saturate_cast<uchar>(value * 1.1));
      frame.depth.at<float>(v, u) = static_cast<float>(best);  // d_c has z = 1: t is depth
    }
  }
  return frame;
}

// A camera pose in the room: position, then rotation about the camera's own axes (radians).
inline Eigen::Isometry3d cameraPose(double x, double y, double z, double rx = 0.0, double ry = 0.0,
                                    double rz = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, z);
  T.linear() = (Eigen::AngleAxisd(ry, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(rx, Eigen::Vector3d::UnitX()) *
                Eigen::AngleAxisd(rz, Eigen::Vector3d::UnitZ()))
                   .toRotationMatrix();
  return T;
}

}  // namespace test
}  // namespace pf2
