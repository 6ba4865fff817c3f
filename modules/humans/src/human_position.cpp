#include "pf2/humans/human_position.h"

#include <cmath>

#include "pf2/core/error.h"

namespace pf2 {

double meanDepth(const cv::Mat& depth) {
  if (depth.empty()) return 0.0;
  if (depth.type() != CV_32F) throw Error("meanDepth: expected a CV_32F depth image");
  double sum = 0.0;
  long count = 0;
  for (int v = 0; v < depth.rows; ++v) {
    const float* row = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; ++u) {
      const float z = row[u];
      if (z > 0.0f && std::isfinite(z)) {
        sum += z;
        ++count;
      }
    }
  }
  return count > 0 ? sum / count : 0.0;
}

Eigen::Vector3d humanCentreInCamera(double x_ul, double y_ul, double x_lr, double y_lr,
                                    double mean_depth, const CameraIntrinsics& intrinsics) {
  const double d = mean_depth;
  return {(x_ul + x_lr - 2.0 * intrinsics.cx) / (2.0 * intrinsics.fx) * d,
          (y_ul + y_lr - 2.0 * intrinsics.cy) / (2.0 * intrinsics.fy) * d, d};
}

}  // namespace pf2
