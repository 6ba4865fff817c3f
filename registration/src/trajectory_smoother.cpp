#include "pf2/registration/trajectory_smoother.h"

#include <algorithm>
#include <cmath>

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "pf2/core/error.h"

namespace pf2 {

TrajectorySmoother::TrajectorySmoother(const Options& options) : options_(options) {
  if (!options_.measure_acceleration) return;
  if (!(options_.acceleration_baseline > 0.0) || !(options_.acceleration_scale > 0.0) ||
      !(options_.acceleration_floor > 0.0))
    throw Error("TrajectorySmoother: acceleration_baseline, acceleration_scale and acceleration_floor must be > 0");
}

Trajectory TrajectorySmoother::smooth(const Trajectory& measured, const std::vector<bool>& restarts) const {
  Trajectory out = measured;
  if (options_.position_noise <= 0.0 || options_.acceleration_noise <= 0.0) return out;
  const double acceleration_noise = accelerationNoise(measured, restarts);
  for (const auto& [begin, end] : segments(measured, restarts)) smoothSegment(measured, begin, end, acceleration_noise, &out);
  return out;
}

std::vector<std::pair<size_t, size_t>> TrajectorySmoother::segments(const Trajectory& measured,
                                                                    const std::vector<bool>& restarts) const {
  std::vector<std::pair<size_t, size_t>> pieces;
  size_t begin = 0;
  for (size_t i = 1; i <= measured.size(); ++i) {
    const bool ends = i == measured.size() || (i < restarts.size() && restarts[i]) ||
                      measured[i].timestamp - measured[i - 1].timestamp > options_.max_gap;
    if (!ends) continue;
    pieces.emplace_back(begin, i);
    begin = i;
  }
  return pieces;
}

// Each piece's positions are sampled every baseline seconds (linear between frames) and their
// second differences pooled per axis; fewer than three of them and the configured value stands.
double TrajectorySmoother::accelerationNoise(const Trajectory& measured, const std::vector<bool>& restarts) const {
  if (!options_.measure_acceleration) return options_.acceleration_noise;
  const double h = options_.acceleration_baseline;
  Eigen::Vector3d sum_squares = Eigen::Vector3d::Zero();
  int count = 0;
  for (const auto& [begin, end] : segments(measured, restarts)) {
    std::vector<Eigen::Vector3d> samples;
    size_t frame = begin;
    for (double t = measured[begin].timestamp; t <= measured[end - 1].timestamp; t += h) {
      while (frame + 1 < end && measured[frame + 1].timestamp < t) ++frame;
      const StampedPose& a = measured[frame];
      const StampedPose& b = measured[std::min(frame + 1, end - 1)];
      const double span = b.timestamp - a.timestamp;
      const double w = span > 0.0 ? std::clamp((t - a.timestamp) / span, 0.0, 1.0) : 0.0;
      samples.push_back((1.0 - w) * a.T_w_c.translation() + w * b.T_w_c.translation());
    }
    for (size_t j = 2; j < samples.size(); ++j) {
      const Eigen::Vector3d acceleration = (samples[j] - 2.0 * samples[j - 1] + samples[j - 2]) / (h * h);
      sum_squares += acceleration.cwiseProduct(acceleration);
      ++count;
    }
  }
  if (count < 3) return options_.acceleration_noise;
  const double busiest_rms = std::sqrt(sum_squares.maxCoeff() / count);
  return std::max(options_.acceleration_floor, options_.acceleration_scale * busiest_rms);
}

// The normal equations of the segment's least-squares problem (the header's cost), one sparse
// symmetric system shared by the three coordinates: measurement rows on the diagonal, and per
// inner frame i the velocity change row c = [1/dt-, -(1/dt- + 1/dt+), 1/dt+] / (a * dt_i) on
// frames i-1, i, i+1.
void TrajectorySmoother::smoothSegment(const Trajectory& measured, size_t begin, size_t end, double acceleration_noise,
                                       Trajectory* out) const {
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
    const double scale = acceleration_noise * 0.5 * (dt_in + dt_out);
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
