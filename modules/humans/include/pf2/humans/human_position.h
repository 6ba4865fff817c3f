#pragma once
// Where a person is (paper §III-B): eq. 2 puts the centre of the person's box at the mean depth
// d_m of the person's depth pixels D_h^t (not the depth at the box centre, which misses a body
// that is not upright); eq. 3 moves it into the world with the camera pose, p_w = T_w_c p_c.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"

namespace pf2 {

// Mean of the measured depths (finite, > 0) of a CV_32F image in metres; 0 when there is none.
// Throws pf2::Error for another image type. Thread safe.
double meanDepth(const cv::Mat& depth);
// The same over the depths inside (min_depth, max_depth) only, e.g. the person's principal depth
// interval: pixels a dilated mask or box took from a person in front or the wall behind stay out.
// `count` (optional) receives the number of depths averaged.
double meanDepth(const cv::Mat& depth, double min_depth, double max_depth, long* count = nullptr);

// Eq. 2: p_c = ((x_ul + x_lr - 2 c_x) / (2 f_x) d_m, (y_ul + y_lr - 2 c_y) / (2 f_y) d_m, d_m) for
// the box corners (x_ul, y_ul), (x_lr, y_lr) in pixels and the mean depth d_m in metres. Thread safe.
Eigen::Vector3d humanCentreInCamera(double x_ul, double y_ul, double x_lr, double y_lr,
                                    double mean_depth, const CameraIntrinsics& intrinsics);

// Eq. 3: the centre in the world frame.
inline Eigen::Vector3d humanCentreInWorld(const Eigen::Isometry3d& T_w_c, const Eigen::Vector3d& p_c) {
  return T_w_c * p_c;
}

}  // namespace pf2
