#include "pf2/body/body_surface_aligner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <Eigen/Geometry>

#include "pf2/core/error.h"

namespace pf2 {

namespace {

// The image in cells of cell_px pixels, each holding a value (initially `empty`); pixels outside
// the image have no cell (the person's points all lie inside it).
class CellImage {
 public:
  CellImage(const CameraIntrinsics& K, double cell_px, float empty)
      : cell_px_(cell_px),
        columns_(static_cast<int>(std::ceil(K.width / cell_px))),
        rows_(static_cast<int>(std::ceil(K.height / cell_px))),
        values_(static_cast<std::size_t>(columns_) * rows_, empty) {}

  // The cell of a pixel, nullptr outside the image (and for NaN).
  float* at(const Eigen::Vector2d& px) {
    const double column = px.x() / cell_px_, row = px.y() / cell_px_;
    if (!(column >= 0 && column < columns_ && row >= 0 && row < rows_)) return nullptr;
    return &values_[static_cast<std::size_t>(row) * columns_ + static_cast<std::size_t>(column)];
  }

  // Each non-zero cell divided by the same cell of `counts` (sums into means).
  void divideNonZero(const CellImage& counts) {
    for (std::size_t i = 0; i < values_.size(); ++i) {
      if (values_[i] != 0) values_[i] /= counts.values_[i];
    }
  }

 private:
  double cell_px_;
  int columns_, rows_;
  std::vector<float> values_;
};

// A vertex of the surface the camera sees, and its share of the image: a third of its triangles'
// area, foreshortened, over z^2 (so that the quantile weighs the surface as the pixels do, not by
// how densely the mesh is made there).
struct VisibleVertex {
  Eigen::Vector3f p;
  double weight;
};

// The torso's vertices facing the camera and not hidden behind a nearer part of the body (within
// occlusion_depth of the nearest vertex of their image cell of cell_px; the nearest vertex of a
// cell is on a camera-facing surface, so the cells need no normals). torso_triangles: the
// triangles that touch a torso vertex, from which the torso vertices' normals come.
std::vector<VisibleVertex> visibleTorso(const BodyMesh& mesh, const std::vector<int>& torso,
                                        const std::vector<int>& torso_triangles, const CameraIntrinsics& K,
                                        double cell_px, double occlusion_depth) {
  CellImage nearest(K, cell_px, std::numeric_limits<float>::infinity());
  for (const Eigen::Vector3f& p : mesh.vertices) {
    float* cell = p.z() > 0.05f ? nearest.at(K.project(p.cast<double>())) : nullptr;
    if (cell) *cell = std::min(*cell, p.z());
  }
  std::vector<Eigen::Vector3f> normals(mesh.vertices.size(), Eigen::Vector3f::Zero());
  for (const int i : torso_triangles) {
    const Eigen::Vector3i& t = mesh.triangles[i];
    // Unnormalised: twice the triangle's area along its normal.
    const Eigen::Vector3f n =
        (mesh.vertices[t[1]] - mesh.vertices[t[0]]).cross(mesh.vertices[t[2]] - mesh.vertices[t[0]]);
    for (int k = 0; k < 3; ++k) normals[t[k]] += n;
  }
  std::vector<VisibleVertex> visible;
  for (const int v : torso) {
    const Eigen::Vector3f& p = mesh.vertices[v];
    if (!(p.z() > 0.05f) || normals[v].dot(p) >= 0) continue;
    const float* cell = nearest.at(K.project(p.cast<double>()));
    if (!cell || p.z() > *cell + occlusion_depth) continue;
    visible.push_back({p, -normals[v].dot(p) / p.norm() / (p.z() * p.z())});
  }
  return visible;
}

// The measured depth per image cell of cell_px: the mean of the points in it, 0 = none.
CellImage measuredDepth(const std::vector<Eigen::Vector3d>& points_c, const CameraIntrinsics& K, double cell_px) {
  CellImage sum(K, cell_px, 0.0f), count(K, cell_px, 0.0f);
  for (const Eigen::Vector3d& p : points_c) {
    if (!p.allFinite() || !(p.z() > 0)) continue;
    const Eigen::Vector2d px = K.project(p);
    float* s = sum.at(px);
    if (!s) continue;
    *s += static_cast<float>(p.z());
    *count.at(px) += 1.0f;
  }
  sum.divideNonZero(count);
  return sum;
}

// The weighted quantile q of (value, weight) pairs; pairs must not be empty.
double weightedQuantile(std::vector<std::pair<double, double>>* pairs, double q) {
  std::sort(pairs->begin(), pairs->end());
  double total = 0;
  for (const auto& [value, weight] : *pairs) total += weight;
  double below = 0;
  for (const auto& [value, weight] : *pairs) {
    below += weight;
    if (below >= q * total) return value;
  }
  return pairs->back().first;
}

}  // namespace

BodySurfaceAligner::BodySurfaceAligner(const BodyModel& model, const Options& options)
    : model_(model), options_(options) {
  if (!(options.cell_px >= 1 && options.cell_px <= 32 && options.match_px >= 1 && options.match_px <= 32 &&
        options.occlusion_depth > 0 && options.occlusion_depth <= 1 && options.min_vertices >= 1 &&
        options.min_vertices <= 1000000 && options.max_shift >= 0 && options.max_shift <= 10 && options.quantile > 0 &&
        options.quantile < 1)) {
    throw Error("BodySurfaceAligner: an option is out of range (cell_px and match_px [1, 32] px, occlusion_depth "
                "(0, 1] m, min_vertices [1, 1e6], max_shift [0, 10] m, quantile (0, 1))");
  }
  // The torso: vertices moved most by the pelvis, the spine or the collars.
  const Eigen::MatrixXf& weights = model.weights();
  std::vector<bool> in_torso(weights.rows());
  for (Eigen::Index v = 0; v < weights.rows(); ++v) {
    Eigen::Index joint = 0;
    weights.row(v).maxCoeff(&joint);
    in_torso[v] = joint == 0 || joint == 3 || joint == 6 || joint == 9 || joint == 13 || joint == 14;
    if (in_torso[v]) torso_.push_back(static_cast<int>(v));
  }
  for (std::size_t i = 0; i < model.triangles().size(); ++i) {
    const Eigen::Vector3i& t = model.triangles()[i];
    if (in_torso[t[0]] || in_torso[t[1]] || in_torso[t[2]]) torso_triangles_.push_back(static_cast<int>(i));
  }
}

BodySurfaceAligner::Result BodySurfaceAligner::align(const std::vector<Eigen::Vector3d>& points_c,
                                                     const CameraIntrinsics& K, BodyParameters* body_c) const {
  Result result;
  const BodyMesh mesh = model_.evaluate(*body_c);
  CellImage measured = measuredDepth(points_c, K, options_.match_px);
  std::vector<std::pair<double, double>> differences;  // (measured - vertex depth, weight)
  for (const VisibleVertex& v :
       visibleTorso(mesh, torso_, torso_triangles_, K, options_.cell_px, options_.occlusion_depth)) {
    const float* depth = measured.at(K.project(v.p.cast<double>()));
    if (depth && *depth > 0) differences.emplace_back(*depth - v.p.z(), v.weight);
  }
  result.vertices = static_cast<int>(differences.size());
  if (result.vertices < options_.min_vertices) return result;
  const double shift_z = weightedQuantile(&differences, options_.quantile);
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
