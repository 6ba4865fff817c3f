#pragma once
// Image helpers shared by the filter and its additions (not part of the public interface).
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"

namespace pf2 {

// Forward-warps depth (and a companion CV_8U image) into another view, nearest point wins. The
// outputs are reused when they already have the right size. Only source pixels inside source_area
// are read (the caller knows the rest is zero). Returns the bounds of what landed. Thread safe for
// distinct outputs.
cv::Rect warpWithCompanion(const cv::Mat& depth_src, const cv::Mat& companion_src, const CameraIntrinsics& K,
                           const Eigen::Isometry3d& T_dst_src, const cv::Rect& source_area, cv::Mat* depth_dst,
                           cv::Mat* companion_dst);

// Dilation of a CV_8U image by OpenCV's elliptic structuring element of size 2 radius + 1, zero
// outside the image: equal to cv::dilate with that kernel, but computed from the kernel's row spans
// (radius passes spreading each row by one pixel, then one maximum per kernel row) instead of one
// pass per kernel pixel, which made cv::dilate the filter's largest cost at the 20-pixel mask reach
// (1293 pixels). Thread safe.
cv::Mat dilatedByDisc(const cv::Mat& image, int radius);

// The mask's pixels dilated by `radius` (a disc), as an image of `area`'s size: the mask's
// bounding box grown by radius, clipped to the image. Empty (and area empty) for an empty mask.
cv::Mat dilatedOnArea(const cv::Mat& mask, int radius, cv::Rect* area);

// The half-resolution grid of an image (every second pixel and row, rounded up).
inline cv::Size halfSize(const cv::Size& size) { return cv::Size((size.width + 1) / 2, (size.height + 1) / 2); }

}  // namespace pf2
