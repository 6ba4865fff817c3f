#include "pf2/body/body_surface_aligner.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>

#include <Eigen/Geometry>

#include "pf2/core/error.h"

namespace pf2 {

namespace {

// Image cells of cell_px pixels over the image and one image's size around it (a body may reach
// beyond the view); key -1 for a pixel beyond that.
class CellGrid {
 public:
  CellGrid(const CameraIntrinsics& K, double cell_px)
      : cell_px_(cell_px),
        width_(K.width),
        height_(K.height),
        columns_(static_cast<long>(std::ceil(3.0 * K.width / cell_px))),
        rows_(static_cast<long>(std::ceil(3.0 * K.height / cell_px))) {}

  long key(const Eigen::Vector2d& px) const {
    const long column = static_cast<long>(std::floor((px.x() + width_) / cell_px_));
    const long row = static_cast<long>(std::floor((px.y() + height_) / cell_px_));
    if (!(column >= 0 && column < columns_ && row >= 0 && row < rows_)) return -1;
    return row * columns_ + column;
  }

 private:
  double cell_px_, width_, height_;
  long columns_, rows_;
};

// A vertex of the surface the camera sees, and its share of the image: a third of its triangles'
// area, foreshortened, over z^2 (so that the median weighs the surface as the pixels do, not by
// how densely the mesh is made there).
struct VisibleVertex {
  Eigen::Vector3f p;
  double weight;
};

// The torso's vertices (selected) facing the camera and not hidden behind a nearer part of the
// body (within occlusion_depth of the nearest camera-facing vertex of their image cell).
std::vector<VisibleVertex> visibleVertices(const BodyMesh& mesh, const std::vector<bool>& selected,
                                           const CameraIntrinsics& K, const CellGrid& grid, double occlusion_depth) {
  std::vector<Eigen::Vector3f> normals(mesh.vertices.size(), Eigen::Vector3f::Zero());
  for (const Eigen::Vector3i& t : mesh.triangles) {
    // Unnormalised: twice the triangle's area along its normal.
    const Eigen::Vector3f n =
        (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    for (int k = 0; k < 3; ++k) normals[t[k]] += n;
  }
  std::vector<std::pair<long, std::size_t>> facing;  // (cell, vertex)
  std::unordered_map<long, float> nearest;           // cell -> nearest camera-facing depth
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    const Eigen::Vector3f& p = mesh.vertices[v];
    if (!(p.z() > 0.05f) || normals[v].dot(p) >= 0) continue;
    const long key = grid.key(K.project(p.cast<double>()));
    if (key < 0) continue;
    facing.emplace_back(key, v);
    auto [it, inserted] = nearest.emplace(key, p.z());
    if (!inserted) it->second = std::min(it->second, p.z());
  }
  std::vector<VisibleVertex> visible;
  for (const auto& [key, v] : facing) {
    const Eigen::Vector3f& p = mesh.vertices[v];
    if (!selected[v] || p.z() > nearest[key] + occlusion_depth) continue;
    visible.push_back({p, -normals[v].dot(p) / p.norm() / (p.z() * p.z())});
  }
  return visible;
}

// The measured depth per image cell (mean of the points in it).
std::unordered_map<long, float> measuredDepthByCell(const std::vector<Eigen::Vector3d>& points_c,
                                                    const CameraIntrinsics& K, const CellGrid& grid) {
  std::unordered_map<long, std::pair<double, int>> sums;
  for (const Eigen::Vector3d& p : points_c) {
    if (!p.allFinite() || !(p.z() > 0)) continue;
    const long key = grid.key(K.project(p));
    if (key < 0) continue;
    auto& [sum, count] = sums[key];
    sum += p.z(), ++count;
  }
  std::unordered_map<long, float> depth;
  depth.reserve(sums.size());
  for (const auto& [key, sum] : sums) depth.emplace(key, static_cast<float>(sum.first / sum.second));
  return depth;
}

// The weighted median of (value, weight) pairs; pairs must not be empty.
double weightedMedian(std::vector<std::pair<double, double>>* pairs) {
  std::sort(pairs->begin(), pairs->end());
  double total = 0;
  for (const auto& [value, weight] : *pairs) total += weight;
  double below = 0;
  for (const auto& [value, weight] : *pairs) {
    below += weight;
    if (below >= 0.5 * total) return value;
  }
  return pairs->back().first;
}

}  // namespace

BodySurfaceAligner::BodySurfaceAligner(const BodyModel& model, const Options& options)
    : model_(model), options_(options) {
  if (!(options.cell_px >= 1 && options.cell_px <= 32 && options.match_px >= 1 && options.match_px <= 32 &&
        options.occlusion_depth > 0 && options.occlusion_depth <= 1 && options.min_vertices >= 1 &&
        options.min_vertices <= 1000000 && options.max_shift >= 0 && options.max_shift <= 10)) {
    throw Error("BodySurfaceAligner: an option is out of range (cell_px and match_px [1, 32] px, occlusion_depth "
                "(0, 1] m, min_vertices [1, 1e6], max_shift [0, 10] m)");
  }
  // The torso: vertices moved most by the pelvis, the spine or the collars.
  const Eigen::MatrixXf& weights = model.weights();
  torso_.resize(weights.rows());
  for (Eigen::Index v = 0; v < weights.rows(); ++v) {
    Eigen::Index joint = 0;
    weights.row(v).maxCoeff(&joint);
    torso_[v] = joint == 0 || joint == 3 || joint == 6 || joint == 9 || joint == 13 || joint == 14;
  }
}

BodySurfaceAligner::Result BodySurfaceAligner::align(const std::vector<Eigen::Vector3d>& points_c,
                                                     const CameraIntrinsics& K, BodyParameters* body_c) const {
  Result result;
  const BodyMesh mesh = model_.evaluate(*body_c);
  const CellGrid match(K, options_.match_px);
  const std::unordered_map<long, float> measured = measuredDepthByCell(points_c, K, match);
  std::vector<std::pair<double, double>> differences;  // (measured - vertex depth, weight)
  for (const VisibleVertex& v :
       visibleVertices(mesh, torso_, K, CellGrid(K, options_.cell_px), options_.occlusion_depth)) {
    const auto it = measured.find(match.key(K.project(v.p.cast<double>())));
    if (it != measured.end()) differences.emplace_back(it->second - v.p.z(), v.weight);
  }
  result.vertices = static_cast<int>(differences.size());
  if (result.vertices < options_.min_vertices) return result;
  const double shift_z = weightedMedian(&differences);
  const Eigen::Vector3d pelvis = mesh.joints[0];
  if (std::abs(shift_z) > options_.max_shift || !(pelvis.z() > 0.05)) return result;
  // Along the ray through the pelvis: the body keeps its place in the image.
  const Eigen::Vector3d move = pelvis * (shift_z / pelvis.z());
  body_c->translation += move;
  result.applied = true;
  result.shift = shift_z < 0 ? -move.norm() : move.norm();
  return result;
}

}  // namespace pf2
