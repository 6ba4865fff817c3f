#include "pf2/registration/gap_interpolator.h"

#include <cmath>

#include "pf2/core/pose.h"

namespace pf2 {

std::vector<size_t> GapInterpolator::fill(std::vector<RunFrame>* frames) const {
  std::vector<size_t> filled;
  if (!(options_.max_gap > 0)) return filled;
  const std::vector<RunFrame>& f = *frames;
  size_t i = 0;
  while (i < f.size()) {
    if (f[i].measured) {
      ++i;
      continue;
    }
    size_t after = i;
    while (after < f.size() && !f[after].measured) ++after;
    // A gap at the start has no measured frame before it, one at the end none after it.
    if (i > 0 && after < f.size() && f[after].timestamp - f[i - 1].timestamp <= options_.max_gap) {
      fillGap(i - 1, after, frames);
      for (size_t k = i; k < after; ++k) filled.push_back(k);
    }
    i = after;
  }
  return filled;
}

bool GapInterpolator::endVelocity(const std::vector<RunFrame>& frames, size_t end, int step,
                                  Eigen::Vector3d* velocity) const {
  size_t far = end;
  for (long k = static_cast<long>(end) + step; k >= 0 && k < static_cast<long>(frames.size()); k += step) {
    const RunFrame& frame = frames[static_cast<size_t>(k)];
    // Of two neighbours, the later one's restart cuts the motion between them.
    const bool cut = step < 0 ? frames[static_cast<size_t>(k) + 1].restarts : frame.restarts;
    if (!frame.measured || cut || std::abs(frame.timestamp - frames[end].timestamp) > options_.velocity_window) break;
    far = static_cast<size_t>(k);
  }
  const double dt = frames[end].timestamp - frames[far].timestamp;
  if (far == end || !(std::abs(dt) > 0)) return false;
  *velocity = (frames[end].T_w_c.translation() - frames[far].T_w_c.translation()) / dt;
  return true;
}

// Cubic Hermite between the two measured ends: position and velocity match at both ends.
void GapInterpolator::fillGap(size_t before, size_t after, std::vector<RunFrame>* frames) const {
  std::vector<RunFrame>& f = *frames;
  const Eigen::Isometry3d& A = f[before].T_w_c;
  const Eigen::Isometry3d& B = f[after].T_w_c;
  const double t0 = f[before].timestamp, span = f[after].timestamp - t0;
  if (!(span > 0)) return;
  const Eigen::Vector3d mean_velocity = (B.translation() - A.translation()) / span;
  Eigen::Vector3d v0 = mean_velocity, v1 = mean_velocity;
  endVelocity(f, before, -1, &v0);
  endVelocity(f, after, +1, &v1);
  for (size_t k = before + 1; k < after; ++k) {
    const double s = (f[k].timestamp - t0) / span;
    const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s;
    const double h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
    Eigen::Isometry3d T = interpolate(A, B, s);
    T.translation() = h00 * A.translation() + h10 * span * v0 + h01 * B.translation() + h11 * span * v1;
    f[k].T_w_c = T;
    f[k].has_pose = true;
  }
}

}  // namespace pf2
