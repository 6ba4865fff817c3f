#include "pf2/surface/map_evaluator.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "pf2/core/error.h"
#include "pf2/core/stage_timer.h"

namespace pf2 {

double pointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c) {
  // Regions of the triangle's plane: three vertices, three edges, the face (barycentric tests).
  const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.norm();
  const Eigen::Vector3d bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.norm();
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).norm();
  const Eigen::Vector3d cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.norm();
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).norm();
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).norm();
  }
  const double sum = va + vb + vc;
  if (!(std::abs(sum) > 0)) return std::min({ap.norm(), bp.norm(), cp.norm()});  // degenerate
  return (p - (a + ab * (vb / sum) + ac * (vc / sum))).norm();
}

MeshDistance::MeshDistance(const TriangleMesh& mesh, double max_distance, double cell_size)
    : max_distance_(max_distance), cell_size_(cell_size) {
  if (!(max_distance > 0) || !(cell_size > 0)) throw Error("MeshDistance: distances must be positive");
  const double half_diagonal = 0.5 * std::sqrt(3.0) * cell_size_;
  for (const Eigen::Vector3i& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>(), b = mesh.vertices[t[1]].cast<double>(),
                          c = mesh.vertices[t[2]].cast<double>();
    const int index = static_cast<int>(a_.size());
    a_.push_back(a);
    b_.push_back(b);
    c_.push_back(c);
    const Eigen::Vector3i lo = cellOf(a.cwiseMin(b).cwiseMin(c)), hi = cellOf(a.cwiseMax(b).cwiseMax(c));
    Eigen::Vector3d normal = (b - a).cross(c - a);
    const bool planar_test = normal.norm() > 0;
    if (planar_test) normal.normalize();
    for (int x = lo.x(); x <= hi.x(); ++x) {
      for (int y = lo.y(); y <= hi.y(); ++y) {
        for (int z = lo.z(); z <= hi.z(); ++z) {
          // Skip cells the triangle's plane does not pass through (large sloped triangles).
          const Eigen::Vector3d centre = (Eigen::Vector3d(x, y, z) + Eigen::Vector3d::Constant(0.5)) * cell_size_;
          if (planar_test && std::abs(normal.dot(centre - a)) > half_diagonal) continue;
          cells_[key(Eigen::Vector3i(x, y, z))].push_back(index);
        }
      }
    }
  }
}

Eigen::Vector3i MeshDistance::cellOf(const Eigen::Vector3d& p) const {
  return (p / cell_size_).array().floor().cast<int>();
}

std::uint64_t MeshDistance::key(const Eigen::Vector3i& cell) {
  const auto field = [](int x) { return static_cast<std::uint64_t>(x + (1 << 20)) & 0x1FFFFFu; };
  return (field(cell.x()) << 42) | (field(cell.y()) << 21) | field(cell.z());
}

double MeshDistance::distance(const Eigen::Vector3d& p) const {
  const Eigen::Vector3i centre = cellOf(p);
  const int rings = static_cast<int>(std::ceil(max_distance_ / cell_size_));
  double best = max_distance_;
  for (int ring = 0; ring <= rings; ++ring) {
    // Anything in ring k+1 or beyond is at least k cells away: stop once the best beats that.
    if (best <= (ring - 1) * cell_size_) break;
    for (int x = -ring; x <= ring; ++x) {
      for (int y = -ring; y <= ring; ++y) {
        for (int z = -ring; z <= ring; ++z) {
          if (std::max({std::abs(x), std::abs(y), std::abs(z)}) != ring) continue;
          const auto it = cells_.find(key(centre + Eigen::Vector3i(x, y, z)));
          if (it == cells_.end()) continue;
          for (int t : it->second) best = std::min(best, pointTriangleDistance(p, a_[t], b_[t], c_[t]));
        }
      }
    }
  }
  return best;
}

std::string completenessBreakdown(const MapQuality& q) {
  std::string text;
  char line[128];
  const auto add = [&](const char* what, const char* format, const std::vector<CompletenessBin>& bins) {
    for (const CompletenessBin& b : bins) {
      if (b.seen == 0) continue;
      std::snprintf(line, sizeof(line), format, what, b.lower, b.upper, 100.0 * b.covered / b.seen, b.seen);
      text += line;
    }
  };
  add("nearest view", "  %s %.1f-%.1f m: %.1f %% of %zu seen samples\n", q.by_range);
  add("incidence", "  %s %.0f-%.0f deg: %.1f %% of %zu seen samples\n", q.by_incidence);
  return text;
}

MapEvaluator::MapEvaluator(const TriangleMesh& ground_truth, const Options& options)
    : options_(options), ground_truth_(ground_truth, options.max_distance, std::max(0.02, options.max_distance / 4)) {
  if (!(options_.sample_spacing > 0)) throw Error("MapEvaluator: sample_spacing must be positive");
  // Samples on a barycentric grid per triangle, about sample_spacing apart.
  for (const Eigen::Vector3i& t : ground_truth.triangles) {
    const Eigen::Vector3d a = ground_truth.vertices[t[0]].cast<double>(),
                          b = ground_truth.vertices[t[1]].cast<double>(),
                          c = ground_truth.vertices[t[2]].cast<double>();
    const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
    const Eigen::Vector3d cross = (b - a).cross(c - a);
    const Eigen::Vector3f normal =
        cross.norm() > 0 ? Eigen::Vector3f(cross.normalized().cast<float>()) : Eigen::Vector3f::Zero();
    const int n = std::max(1, static_cast<int>(std::ceil(longest / options_.sample_spacing)));
    // Interior points only (i, j >= 1 off the shared edges), so neighbours don't double-count edges.
    for (int i = 0; i < n; ++i) {
      for (int j = 0; i + j < n; ++j) {
        const double s = (i + 1.0 / 3.0) / n, r = (j + 1.0 / 3.0) / n;
        samples_.push_back(a + s * (b - a) + r * (c - a));
        normals_.push_back(normal);
      }
    }
  }
  seen_.assign(samples_.size(), 0);
  nearest_depth_.assign(samples_.size(), std::numeric_limits<float>::infinity());
  best_cosine_.assign(samples_.size(), 0.f);
}

void MapEvaluator::markSeen(const cv::Mat& depth, const CameraIntrinsics& K, const Eigen::Isometry3d& T_w_c) {
  if (depth.type() != CV_32FC1 || depth.cols != K.width || depth.rows != K.height) {
    throw Error("MapEvaluator: depth must be CV_32F of the intrinsics' size");
  }
  const Eigen::Isometry3d T_c_w = T_w_c.inverse();
  const Eigen::Vector3d centre_w = T_w_c.translation();
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    const Eigen::Vector3d p_c = T_c_w * samples_[i];
    if (p_c.z() <= 0.05) continue;
    const Eigen::Vector2d uv = K.project(p_c);
    const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
    if (u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) continue;
    const float d = depth.at<float>(v, u);
    if (!(d > 0 && std::abs(d - p_c.z()) <= options_.seen_tolerance)) continue;
    seen_[i] = 1;
    nearest_depth_[i] = std::min(nearest_depth_[i], static_cast<float>(p_c.z()));
    const float cosine = std::abs(normals_[i].dot((samples_[i] - centre_w).normalized().cast<float>()));
    best_cosine_[i] = std::max(best_cosine_[i], cosine);
  }
}

void MapEvaluator::markAllSeen() {
  std::fill(seen_.begin(), seen_.end(), 1);
  std::fill(nearest_depth_.begin(), nearest_depth_.end(), 0.f);
  std::fill(best_cosine_.begin(), best_cosine_.end(), 1.f);
}

MapQuality MapEvaluator::evaluate(const TriangleMesh& map) const {
  MapQuality quality;
  quality.map_vertices = map.vertices.size();
  std::vector<double> distances;
  distances.reserve(map.vertices.size());
  for (const Eigen::Vector3f& v : map.vertices) {
    const double d = ground_truth_.distance(v.cast<double>());
    distances.push_back(d);
    quality.ghost_vertices += d > options_.ghost_distance;
  }
  if (!distances.empty()) {
    double sum = 0.0;
    for (double d : distances) sum += d;
    quality.mean = sum / distances.size();
    quality.max = *std::max_element(distances.begin(), distances.end());
    quality.median = percentile(distances, 50);
    quality.p90 = percentile(distances, 90);
  }
  const MeshDistance to_map(map, options_.completeness_distance * 1.5, 0.02);
  constexpr double kRangeBin = 0.5, kAngleBin = 15.0;
  const auto bin = [](std::vector<CompletenessBin>* bins, double value, double width) -> CompletenessBin& {
    const std::size_t k = static_cast<std::size_t>(std::max(0.0, value / width));
    while (bins->size() <= k) {
      const double lower = bins->size() * width;
      bins->push_back({lower, lower + width, 0, 0});
    }
    return (*bins)[k];
  };
  std::size_t covered = 0;
  for (std::size_t i = 0; i < samples_.size(); ++i) {
    if (!seen_[i]) continue;
    ++quality.seen_samples;
    const bool near = to_map.distance(samples_[i]) <= options_.completeness_distance;
    covered += near;
    const double angle = std::acos(std::min(1.f, best_cosine_[i])) * 180.0 / std::acos(-1.0);
    for (CompletenessBin* b : {&bin(&quality.by_range, nearest_depth_[i], kRangeBin),
                               &bin(&quality.by_incidence, std::min(angle, 89.999), kAngleBin)}) {
      ++b->seen;
      b->covered += near;
    }
  }
  quality.completeness = quality.seen_samples ? static_cast<double>(covered) / quality.seen_samples : 0.0;
  return quality;
}

}  // namespace pf2
