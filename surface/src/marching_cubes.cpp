#include "pf2/surface/marching_cubes.h"

#include <algorithm>

#include <Eigen/Geometry>

namespace pf2 {
namespace marching_cubes {

// The twelve corner pairs that differ in exactly one coordinate bit, lower corner first.
const int kEdgeCorners[12][2] = {{0, 1}, {2, 3}, {4, 5}, {6, 7},   // along x
                                 {0, 2}, {1, 3}, {4, 6}, {5, 7},   // along y
                                 {0, 4}, {1, 5}, {2, 6}, {3, 7}};  // along z
const int kEdgeAxis[12] = {0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2};

namespace {

Eigen::Vector3d cornerPosition(int c) { return Eigen::Vector3d(c & 1, (c >> 1) & 1, (c >> 2) & 1); }

int edgeBetween(int a, int b) {
  for (int e = 0; e < 12; ++e) {
    if ((kEdgeCorners[e][0] == a && kEdgeCorners[e][1] == b) ||
        (kEdgeCorners[e][0] == b && kEdgeCorners[e][1] == a)) {
      return e;
    }
  }
  return -1;
}

std::vector<std::array<int, 3>> buildCase(int cube_case) {
  const auto inside = [cube_case](int c) { return ((cube_case >> c) & 1) != 0; };
  // Each crossed edge gets two neighbours in the loop, one from each of its two faces.
  std::array<std::array<int, 2>, 12> neighbour;
  for (auto& n : neighbour) n = {-1, -1};
  const auto link = [&neighbour](int e, int f) {
    neighbour[e][neighbour[e][0] < 0 ? 0 : 1] = f;
    neighbour[f][neighbour[f][0] < 0 ? 0 : 1] = e;
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      // The face's corners in cyclic order.
      std::array<int, 4> q;
      const int steps[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      for (int k = 0; k < 4; ++k) q[k] = (side << axis) | (steps[k][0] << b) | (steps[k][1] << c);
      std::array<int, 4> edge;  // edge k joins q[k] and q[k+1]
      std::vector<int> crossed;
      for (int k = 0; k < 4; ++k) {
        edge[k] = edgeBetween(q[k], q[(k + 1) % 4]);
        if (inside(q[k]) != inside(q[(k + 1) % 4])) crossed.push_back(edge[k]);
      }
      if (crossed.size() == 2) {
        link(crossed[0], crossed[1]);
      } else if (crossed.size() == 4) {
        // Ambiguous face: cut off each inside corner by joining its two edges.
        for (int k = 0; k < 4; ++k) {
          if (inside(q[k])) link(edge[(k + 3) % 4], edge[k]);
        }
      }
    }
  }
  std::vector<std::array<int, 3>> triangles;
  std::array<bool, 12> used{};
  for (int start = 0; start < 12; ++start) {
    if (used[start] || neighbour[start][0] < 0) continue;
    std::vector<int> loop;
    int previous = -1, current = start;
    while (!used[current]) {
      used[current] = true;
      loop.push_back(current);
      const int next = neighbour[current][0] != previous ? neighbour[current][0] : neighbour[current][1];
      previous = current;
      current = next;
    }
    // Orient the loop so that its normal points from the inside corners to the outside ones.
    Eigen::Vector3d outward = Eigen::Vector3d::Zero(), newell = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < loop.size(); ++i) {
      const int e = loop[i];
      const int lo = kEdgeCorners[e][0], hi = kEdgeCorners[e][1];
      outward += inside(lo) ? cornerPosition(hi) - cornerPosition(lo) : cornerPosition(lo) - cornerPosition(hi);
      const int f = loop[(i + 1) % loop.size()];
      const Eigen::Vector3d pe = 0.5 * (cornerPosition(kEdgeCorners[e][0]) + cornerPosition(kEdgeCorners[e][1]));
      const Eigen::Vector3d pf = 0.5 * (cornerPosition(kEdgeCorners[f][0]) + cornerPosition(kEdgeCorners[f][1]));
      newell += pe.cross(pf);
    }
    if (newell.dot(outward) < 0) std::reverse(loop.begin(), loop.end());
    for (size_t i = 1; i + 1 < loop.size(); ++i) triangles.push_back({loop[0], loop[i], loop[i + 1]});
  }
  return triangles;
}

struct Table {
  std::array<std::vector<std::array<int, 3>>, 256> cases;
  Table() {
    for (int i = 0; i < 256; ++i) cases[i] = buildCase(i);
  }
};

}  // namespace

const std::vector<std::array<int, 3>>& triangles(int cube_case) {
  static const Table table;
  return table.cases[cube_case & 255];
}

}  // namespace marching_cubes
}  // namespace pf2
