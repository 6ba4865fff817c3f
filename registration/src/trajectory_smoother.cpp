#include "pf2/registration/trajectory_smoother.h"

#include <algorithm>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace pf2 {

Trajectory TrajectorySmoother::smooth(const Trajectory& measured, const std::vector<bool>& restarts) const {
  Trajectory out = measured;
  if (options_.position_noise <= 0.0 || options_.acceleration_noise <= 0.0) return out;
  size_t begin = 0;
  for (size_t i = 1; i <= measured.size(); ++i) {
    const bool ends = i == measured.size() || (i < restarts.size() && restarts[i]) ||
                      measured[i].timestamp - measured[i - 1].timestamp > options_.max_gap;
    if (!ends) continue;
    smoothSegment(measured, begin, i, &out);
    begin = i;
  }
  return out;
}

// The normal equations of the segment's least-squares problem (the header's cost), one sparse
// symmetric system shared by the three coordinates: measurement rows on the diagonal, and per
// inner frame i the velocity change row c = [1/dt-, -(1/dt- + 1/dt+), 1/dt+] / (a * dt_i) on
// frames i-1, i, i+1.
void TrajectorySmoother::smoothSegment(const Trajectory& measured, size_t begin, size_t end, Trajectory* out) const {
  const int n = static_cast<int>(end - begin);
  if (n < 3) return;
  const double w_measured = 1.0 / (options_.position_noise * options_.position_noise);
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(10 * n));
  Eigen::MatrixXd rhs(n, 3);
  for (int i = 0; i < n; ++i) {
    entries.emplace_back(i, i, w_measured);
    rhs.row(i) = w_measured * measured[begin + i].T_w_c.translation().transpose();
  }
  for (int i = 1; i + 1 < n; ++i) {
    // Frames at the same instant carry no velocity: a tiny step keeps the row finite.
    const double dt_in = std::max(1e-3, measured[begin + i].timestamp - measured[begin + i - 1].timestamp);
    const double dt_out = std::max(1e-3, measured[begin + i + 1].timestamp - measured[begin + i].timestamp);
    const double scale = options_.acceleration_noise * 0.5 * (dt_in + dt_out);
    const double c[3] = {1.0 / dt_in / scale, -(1.0 / dt_in + 1.0 / dt_out) / scale, 1.0 / dt_out / scale};
    for (int r = 0; r < 3; ++r) {
      for (int s = 0; s < 3; ++s) entries.emplace_back(i - 1 + r, i - 1 + s, c[r] * c[s]);
    }
  }
  Eigen::SparseMatrix<double> normal(n, n);
  normal.setFromTriplets(entries.begin(), entries.end());  // duplicates are summed
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
  if (solver.info() != Eigen::Success) return;  // cannot happen for a positive diagonal; keep measured
  const Eigen::MatrixXd smoothed = solver.solve(rhs);
  for (int i = 0; i < n; ++i) (*out)[begin + i].T_w_c.translation() = smoothed.row(i).transpose();
}

}  // namespace pf2
