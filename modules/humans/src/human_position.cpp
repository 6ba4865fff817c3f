#include "pf2/humans/human_position.h"

#include <cmath>
#include <limits>

#include "pf2/core/error.h"

namespace pf2 {

double meanDepth(const cv::Mat& depth) {
  return meanDepth(depth, 0.0, std::numeric_limits<double>::infinity());
}

double meanDepth(const cv::Mat& depth, double min_depth, double max_depth, long* count_out) {
  if (count_out) *count_out = 0;
  if (depth.empty()) return 0.0;
  if (depth.type() != CV_32F) throw Error("meanDepth: expected a CV_32F depth image");
  double sum = 0.0;
  long count = 0;
  for (int v = 0; v < depth.rows; ++v) {
    const float* row = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; ++u) {
      const float z = row[u];
      if (z > 0.0f && std::isfinite(z) && z > min_depth && z < max_depth) {
        sum += z;
        ++count;
      }
    }
  }
  if (count_out) *count_out = count;
  return count > 0 ? sum / count : 0.0;
}

Eigen::Vector3d humanCentreInCamera(double x_ul, double y_ul, double x_lr, double y_lr,
                                    double mean_depth, const CameraIntrinsics& intrinsics) {
  const double d = mean_depth;
  return {(x_ul + x_lr - 2.0 * intrinsics.cx) / (2.0 * intrinsics.fx) * d,
          (y_ul + y_lr - 2.0 * intrinsics.cy) / (2.0 * intrinsics.fy) * d, d};
}

}  // namespace pf2
