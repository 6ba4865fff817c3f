#include "pf2/synth/depth_sensor_model.h"

#include <cmath>
#include <vector>

#include "pf2/core/error.h"
#include "hash_random.h"
#include "parallel_for.h"

namespace pf2 {

namespace synth {
double gaussianFromTable(std::uint64_t h) {
  static const std::vector<double> table = [] {
    // Inverse normal CDF by bisection on erfc; computed once.
    std::vector<double> values(4096);
    for (size_t k = 0; k < values.size(); ++k) {
      const double p = (k + 0.5) / values.size();
      double lo = -8.0, hi = 8.0;
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
      }
      values[k] = 0.5 * (lo + hi);
    }
    return values;
  }();
  return table[h >> 52];
}
}  // namespace synth

DepthSensorModel::DepthSensorModel(const Options& options) : options_(options) {
  if (!(options.min_depth >= 0.0 && options.max_depth > options.min_depth)) {
    throw Error("DepthSensorModel: need 0 <= min_depth < max_depth");
  }
  if (!(options.baseline > 0.0 && options.disparity_step >= 0.0)) {
    throw Error("DepthSensorModel: baseline must be positive and disparity_step non-negative");
  }
}

double DepthSensorModel::sigma(double z) const {
  const double beyond = z - options_.sigma_offset;
  return options_.sigma_constant + options_.sigma_quadratic * beyond * beyond;
}

cv::Mat DepthSensorModel::apply(const cv::Mat& depth, const CameraIntrinsics& K,
                                std::uint64_t seed) const {
  CV_Assert(depth.type() == CV_32F);
  const int rows = depth.rows, cols = depth.cols;
  cv::Mat result(rows, cols, CV_32F, cv::Scalar(0.0f));
  const double fb = K.fx * options_.baseline;  // disparity (pixels) times depth (metres)
  const float lo = static_cast<float>(options_.min_depth), hi = static_cast<float>(options_.max_depth);

  synth::parallelFor(0, rows, true, [&](int v) {
    const float* in = depth.ptr<float>(v);
    float* out = result.ptr<float>(v);
    // The projector sits to the camera's right: a pixel is in its shadow when a nearer surface
    // further right projects to the left of it in the projector (u - d is not increasing).
    double min_projector_u = 1e30;
    for (int u = cols - 1; u >= 0; --u) {
      const float z = in[u];
      if (!(z > 0.0f)) continue;
      const double projector_u = u - fb / z;
      const bool shadowed = options_.noise && options_.projector_shadows && projector_u > min_projector_u + 0.5;
      min_projector_u = std::min(min_projector_u, projector_u);
      if (shadowed) continue;
      if (!options_.noise) {
        out[u] = z;
        continue;
      }
      const std::uint64_t h = synth::hashOf(seed, static_cast<std::uint64_t>(v), static_cast<std::uint64_t>(u));
      // Mixed pixels at depth edges.
      bool edge = false;
      const float jump = static_cast<float>(options_.edge_relative_jump) * z;
      const int du[4] = {-1, 1, 0, 0}, dv[4] = {0, 0, -1, 1};
      for (int k = 0; k < 4 && !edge; ++k) {
        const int uu = u + du[k], vv = v + dv[k];
        if (uu < 0 || uu >= cols || vv < 0 || vv >= rows) continue;
        const float n = depth.ptr<float>(vv)[uu];
        edge = n > 0.0f && std::fabs(n - z) > jump;
      }
      if (edge && synth::uniform01(synth::mix64(h)) < options_.edge_drop_probability) continue;
      double noisy = z + sigma(z) * synth::gaussianFromTable(h);
      if (options_.disparity_step > 0.0 && noisy > 0.0) {
        const double disparity = fb / noisy;
        noisy = fb / (std::round(disparity / options_.disparity_step) * options_.disparity_step);
      }
      out[u] = static_cast<float>(noisy);
    }
    for (int u = 0; u < cols; ++u) {
      if (out[u] < lo || out[u] > hi) out[u] = 0.0f;
    }
  });
  if (options_.misalign_px == 0) return result;
  cv::Mat shifted(rows, cols, CV_32F, cv::Scalar(0.0f));
  const int s = options_.misalign_px;
  for (int v = 0; v < rows; ++v) {
    const float* in = result.ptr<float>(v);
    float* out = shifted.ptr<float>(v);
    for (int u = std::max(0, s); u < std::min(cols, cols + s); ++u) out[u] = in[u - s];
  }
  return shifted;
}

}  // namespace pf2
