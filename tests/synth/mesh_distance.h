#pragma once
// Test helper: distance from points to a triangle mesh, by brute force over the triangles whose
// bounding box is near enough (the meshes in these tests have at most a few ten thousand triangles).
#include <algorithm>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "pf2/core/median.h"

namespace pf2 {
namespace test {

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
inline Eigen::Vector3d closestOnTriangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                         const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

class MeshDistance {
 public:
  MeshDistance(const std::vector<Eigen::Vector3f>& vertices, const std::vector<Eigen::Vector3i>& triangles) {
    for (const Eigen::Vector3i& t : triangles) {
      Tri tri{vertices[t[0]].cast<double>(), vertices[t[1]].cast<double>(), vertices[t[2]].cast<double>(), {}, {}};
      tri.lo = tri.a.cwiseMin(tri.b).cwiseMin(tri.c);
      tri.hi = tri.a.cwiseMax(tri.b).cwiseMax(tri.c);
      tris_.push_back(tri);
    }
  }
  // Distance to the nearest triangle, or `limit` when none lies within it.
  double distance(const Eigen::Vector3d& p, double limit = 0.05) const {
    double best = limit;
    for (const Tri& t : tris_) {
      if ((p.array() < t.lo.array() - best).any() || (p.array() > t.hi.array() + best).any()) continue;
      best = std::min(best, (closestOnTriangle(p, t.a, t.b, t.c) - p).norm());
    }
    return best;
  }

 private:
  struct Tri {
    Eigen::Vector3d a, b, c, lo, hi;
  };
  std::vector<Tri> tris_;
};

inline double median(std::vector<double> values) {
  return upperMedian(&values, std::numeric_limits<double>::quiet_NaN());
}

}  // namespace test
}  // namespace pf2
