#include "pf2/humans/visible_centre.h"

#include <algorithm>
#include <limits>

#include "pf2/core/error.h"

namespace pf2 {

namespace {

// Vertices nearer than this (m) are behind or at the lens: not seen.
constexpr double kMinDepth = 0.1;

}  // namespace

VisibleCentre::VisibleCentre(const CameraIntrinsics& intrinsics, const Options& options)
    : intrinsics_(intrinsics), options_(options) {
  if (intrinsics.width <= 0 || intrinsics.height <= 0 || !(intrinsics.fx > 0) || !(intrinsics.fy > 0)) {
    throw Error("VisibleCentre: intrinsics need a positive width, height, fx and fy");
  }
  if (options.cell_px < 1 || options.cell_px > 64) throw Error("VisibleCentre: cell_px must be in [1, 64]");
  if (options.max_iterations < 1 || options.max_iterations > 1000) {
    throw Error("VisibleCentre: max_iterations must be in [1, 1000]");
  }
  if (!(options.tolerance > 0 && options.tolerance <= 1)) throw Error("VisibleCentre: tolerance must be in (0, 1] m");
  if (!(options.max_move > 0 && options.max_move <= 10)) throw Error("VisibleCentre: max_move must be in (0, 10] m");
}

bool VisibleCentre::centre(const std::vector<Eigen::Vector3d>& relative_c, const Eigen::Vector3d& pelvis_c,
                           Eigen::Vector3d* centre_c, double* share_in_view) const {
  const CameraIntrinsics& K = intrinsics_;
  const int cell = options_.cell_px;
  const int cols = (K.width + cell - 1) / cell, rows = (K.height + cell - 1) / cell;
  // The box of the vertices inside the image (hidden ones project inside the outline too), and
  // the nearest depth per cell: the visible surface, each cell weighing as its pixels do (by area,
  // not by how densely the mesh has vertices there).
  std::vector<double> nearest(static_cast<size_t>(cols * rows), std::numeric_limits<double>::infinity());
  Eigen::Vector2d low(K.width, K.height), high(0, 0);
  size_t in_view = 0;
  for (const Eigen::Vector3d& r : relative_c) {
    const Eigen::Vector3d p = pelvis_c + r;
    if (p.z() < kMinDepth) continue;
    const Eigen::Vector2d uv = K.project(p);
    if (uv.x() < 0 || uv.y() < 0 || uv.x() >= K.width || uv.y() >= K.height) continue;
    const size_t index = static_cast<size_t>(static_cast<int>(uv.y()) / cell * cols + static_cast<int>(uv.x()) / cell);
    nearest[index] = std::min(nearest[index], p.z());
    low = low.cwiseMin(uv);
    high = high.cwiseMax(uv);
    ++in_view;
  }
  if (share_in_view) *share_in_view = relative_c.empty() ? 0.0 : static_cast<double>(in_view) / relative_c.size();
  double depth_sum = 0;
  int cells = 0;
  for (const double z : nearest) {
    if (z == std::numeric_limits<double>::infinity()) continue;
    depth_sum += z;
    ++cells;
  }
  if (cells == 0) return false;
  const Eigen::Vector2d middle = 0.5 * (low + high);
  *centre_c = K.backProject(middle.x(), middle.y(), depth_sum / cells);
  return true;
}

bool VisibleCentre::pelvisFor(const std::vector<Eigen::Vector3d>& relative_c, const Eigen::Vector3d& target_c,
                              const Eigen::Vector3d& start_c, Eigen::Vector3d* pelvis_c) const {
  Eigen::Vector3d pelvis = start_c;
  for (int step = 0; step < options_.max_iterations; ++step) {
    Eigen::Vector3d modelled;
    if (!centre(relative_c, pelvis, &modelled)) return false;
    const Eigen::Vector3d miss = target_c - modelled;
    pelvis += miss;
    if ((pelvis - start_c).norm() > options_.max_move) return false;
    if (miss.norm() < options_.tolerance) break;
  }
  *pelvis_c = pelvis;
  return true;
}

}  // namespace pf2
