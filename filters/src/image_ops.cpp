#include "image_ops.h"

#include <algorithm>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "pf2/filters/dual_bbox_filter.h"

namespace pf2 {

cv::Mat dilatedByDisc(const cv::Mat& image, int radius) {
  CV_Assert(image.type() == CV_8UC1);
  const int r = std::max(0, radius);
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1));
  // spread[w]: every row's pixels spread w pixels to each side (a (2w + 1) x 1 dilation).
  std::vector<cv::Mat> spread(r + 1);
  spread[0] = image;
  const cv::Mat one_each_side = cv::Mat::ones(1, 3, CV_8U);
  for (int w = 1; w <= r; ++w)
    cv::dilate(spread[w - 1], spread[w], one_each_side, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  // Kernel row dy is the symmetric span of half-width w(dy): output row v takes spread[w(dy)] at row v + dy.
  cv::Mat out(image.size(), CV_8U, cv::Scalar(0));
  for (int dy = -r; dy <= r; ++dy) {
    const uchar* kernel_row = kernel.ptr<uchar>(dy + r);
    int half_width = -1;
    while (half_width < r && kernel_row[r + half_width + 1]) ++half_width;
    const int first = std::max(0, -dy), end = std::min(image.rows, image.rows - dy);
    if (half_width < 0 || first >= end) continue;
    cv::Mat target = out.rowRange(first, end);
    cv::max(target, spread[half_width].rowRange(first + dy, end + dy), target);
  }
  return out;
}

// The mask's pixels dilated by `radius` (a disc), as an image of `area`'s size: the mask's
// bounding box grown by radius, clipped to the image. Empty (and area empty) for an empty mask.
cv::Mat dilatedOnArea(const cv::Mat& mask, int radius, cv::Rect* area) {
  const cv::Rect bounds = cv::boundingRect(mask);
  if (bounds.empty()) {
    *area = cv::Rect();
    return cv::Mat();
  }
  const int r = std::max(0, radius);
  *area = cv::Rect(bounds.x - r, bounds.y - r, bounds.width + 2 * r, bounds.height + 2 * r) &
          cv::Rect(0, 0, mask.cols, mask.rows);
  const cv::Mat binary = mask(*area) > 0;
  return r > 0 ? dilatedByDisc(binary, r) : binary;
}

cv::Rect warpWithCompanion(const cv::Mat& depth_src, const cv::Mat& companion_src,
                           const CameraIntrinsics& K, const Eigen::Isometry3d& T_dst_src,
                           const cv::Rect& source_area, cv::Mat* depth_dst, cv::Mat* companion_dst) {
  depth_dst->create(depth_src.size(), CV_32F);
  depth_dst->setTo(0);
  if (companion_dst) {
    companion_dst->create(depth_src.size(), CV_8U);
    companion_dst->setTo(0);
  }
  int u_min = depth_src.cols, v_min = depth_src.rows, u_max = -1, v_max = -1;
  const Eigen::Matrix3f R = T_dst_src.linear().cast<float>();
  const Eigen::Vector3f t = T_dst_src.translation().cast<float>();
  const float fx = K.fx, fy = K.fy, cx = K.cx, cy = K.cy;
  // p_dst = z * (R (x_n, y_n, 1)) + t with x_n, y_n the normalised coordinates: the rotated ray is
  // a column term plus a row term, computed once per column and per row.
  std::vector<Eigen::Vector3f> column_ray(depth_src.cols);
  for (int u = 0, u_end = depth_src.cols; u < u_end; ++u) column_ray[u] = R.col(0) * ((u - cx) / fx);
  const int width = depth_src.cols, height = depth_src.rows;
  const cv::Rect area = source_area & cv::Rect(0, 0, width, height);
  for (int v = area.y; v < area.y + area.height; ++v) {
    const float* row = depth_src.ptr<float>(v);
    const Eigen::Vector3f row_ray = R.col(1) * ((v - cy) / fy) + R.col(2);
    for (int u = area.x, u_end = area.x + area.width; u < u_end; ++u) {
      const float z = row[u];
      if (!(z > 0.f)) continue;
      const Eigen::Vector3f p_dst = z * (column_ray[u] + row_ray) + t;
      if (!(p_dst.z() > 0.f)) continue;
      const float uf = fx * p_dst.x() / p_dst.z() + cx + 0.5f;
      const float vf = fy * p_dst.y() / p_dst.z() + cy + 0.5f;
      if (!(uf >= 0.f && vf >= 0.f && uf < width && vf < height)) continue;  // also rejects NaN
      const int ud = static_cast<int>(uf), vd = static_cast<int>(vf);  // round to nearest
      u_min = std::min(u_min, ud);
      u_max = std::max(u_max, ud);
      v_min = std::min(v_min, vd);
      v_max = std::max(v_max, vd);
      float& target = depth_dst->at<float>(vd, ud);
      if (target == 0.f || p_dst.z() < target) {
        target = p_dst.z();
        if (companion_dst) companion_dst->at<uint8_t>(vd, ud) = companion_src.at<uint8_t>(v, u);
      }
    }
  }
  return u_max < 0 ? cv::Rect() : cv::Rect(u_min, v_min, u_max - u_min + 1, v_max - v_min + 1);
}

cv::Mat warpDepth(const cv::Mat& depth_src, const CameraIntrinsics& intrinsics,
                  const Eigen::Isometry3d& T_dst_src) {
  cv::Mat out;  // a fresh image: the caller keeps it
  warpWithCompanion(depth_src, cv::Mat(), intrinsics, T_dst_src, cv::Rect(0, 0, depth_src.cols, depth_src.rows), &out,
                    nullptr);
  return out;
}

}  // namespace pf2
