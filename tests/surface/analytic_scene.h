#pragma once
// Exact depth and colour of simple scenes (an inside-out box room, solid boxes, spheres) by ray
// casting, with the exact distance to their surfaces: data for the surface tests and benchmarks.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"
#include "pf2/surface/triangle_mesh.h"

namespace pf2 {
namespace test {

struct Box {
  Eigen::Vector3d min, max;
};
struct Sphere {
  Eigen::Vector3d centre;
  double radius;
};

struct AnalyticScene {
  bool has_room = false;
  Box room;                    // seen from inside
  std::vector<Box> boxes;      // solid, seen from outside
  std::vector<Sphere> spheres;

  // Ray parameter of the first hit of o + t d (t > 0), infinity when none.
  double hit(const Eigen::Vector3d& o, const Eigen::Vector3d& d) const {
    double best = std::numeric_limits<double>::infinity();
    if (has_room) {
      for (int a = 0; a < 3; ++a) {
        if (d[a] > 0) best = std::min(best, (room.max[a] - o[a]) / d[a]);
        if (d[a] < 0) best = std::min(best, (room.min[a] - o[a]) / d[a]);
      }
    }
    for (const Box& box : boxes) {
      double t0 = 0.0, t1 = std::numeric_limits<double>::infinity();
      for (int a = 0; a < 3; ++a) {
        const double inv = 1.0 / d[a];
        double ta = (box.min[a] - o[a]) * inv, tb = (box.max[a] - o[a]) * inv;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
      }
      if (t0 <= t1 && t0 > 0) best = std::min(best, t0);
    }
    for (const Sphere& s : spheres) {
      const Eigen::Vector3d oc = o - s.centre;
      const double b = oc.dot(d), a = d.squaredNorm(), c = oc.squaredNorm() - s.radius * s.radius;
      const double disc = b * b - a * c;
      if (disc < 0) continue;
      const double t = (-b - std::sqrt(disc)) / a;
      if (t > 0) best = std::min(best, t);
    }
    return best;
  }

  // Depth (CV_32F, camera z) and a colour checkerboard of 10 cm squares fixed to the world.
  void render(const CameraIntrinsics& K, const Eigen::Isometry3d& T_w_c, cv::Mat* depth,
              cv::Mat* bgr = nullptr) const {
    depth->create(K.height, K.width, CV_32F);
    if (bgr) bgr->create(K.height, K.width, CV_8UC3);
    const Eigen::Vector3d o = T_w_c.translation();
    for (int v = 0; v < K.height; ++v) {
      for (int u = 0; u < K.width; ++u) {
        const Eigen::Vector3d d_c((u - K.cx) / K.fx, (v - K.cy) / K.fy, 1.0);
        const double t = hit(o, T_w_c.linear() * d_c);
        const bool valid = std::isfinite(t);
        depth->at<float>(v, u) = valid ? static_cast<float>(t) : 0.f;  // d_c.z = 1: t is depth
        if (bgr) {
          cv::Vec3b colour(0, 0, 0);
          if (valid) {
            const Eigen::Vector3d p = o + t * (T_w_c.linear() * d_c);
            const long parity = std::lround(std::floor(p.x() * 10) + std::floor(p.y() * 10) + std::floor(p.z() * 10));
            colour = (parity & 1) ? cv::Vec3b(200, 60, 30) : cv::Vec3b(40, 180, 220);
          }
          bgr->at<cv::Vec3b>(v, u) = colour;
        }
      }
    }
  }

  // Unsigned distance from p to the nearest surface.
  double distance(const Eigen::Vector3d& p) const {
    double best = std::numeric_limits<double>::infinity();
    if (has_room) best = std::min(best, boxDistance(room, p));
    for (const Box& box : boxes) best = std::min(best, boxDistance(box, p));
    for (const Sphere& s : spheres) best = std::min(best, std::abs((p - s.centre).norm() - s.radius));
    return best;
  }

  static double boxDistance(const Box& box, const Eigen::Vector3d& p) {
    const Eigen::Vector3d outside = (box.min - p).cwiseMax(p - box.max).cwiseMax(0.0);
    if (outside.squaredNorm() > 0) return outside.norm();
    return (p - box.min).cwiseMin(box.max - p).minCoeff();
  }
};

// The 4 x 2.7 x 4 m room most tests and benchmarks use (world y points down, floor at y = 1.2).
inline AnalyticScene boxRoom() {
  AnalyticScene scene;
  scene.has_room = true;
  scene.room = {Eigen::Vector3d(-2.0, -1.5, -2.0), Eigen::Vector3d(2.0, 1.2, 2.0)};
  return scene;
}

// A camera at position p_w looking at target_w (y of the image roughly along world -up).
inline Eigen::Isometry3d lookAt(const Eigen::Vector3d& p_w, const Eigen::Vector3d& target_w,
                                const Eigen::Vector3d& up_w = Eigen::Vector3d(0, -1, 0)) {
  const Eigen::Vector3d z = (target_w - p_w).normalized();
  const Eigen::Vector3d y = -(up_w - up_w.dot(z) * z).normalized();  // image y points down
  const Eigen::Vector3d x = y.cross(z);
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  T_w_c.linear().col(0) = x;
  T_w_c.linear().col(1) = y;
  T_w_c.linear().col(2) = z;
  T_w_c.translation() = p_w;
  return T_w_c;
}

// The six inner faces of a box room as 12 triangles (ground truth for the map evaluator).
inline TriangleMesh boxMesh(const Box& box) {
  TriangleMesh mesh;
  for (int c = 0; c < 8; ++c) {
    mesh.vertices.emplace_back((c & 1) ? box.max.x() : box.min.x(), (c & 2) ? box.max.y() : box.min.y(),
                               (c & 4) ? box.max.z() : box.min.z());
  }
  const int quads[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.emplace_back(q[0], q[1], q[2]);
    mesh.triangles.emplace_back(q[0], q[2], q[3]);
  }
  return mesh;
}

}  // namespace test
}  // namespace pf2
