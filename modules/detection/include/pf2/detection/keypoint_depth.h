#pragma once
// The depth a person's keypoints stand on: the median of the measured depths under their confident
// keypoints. A keypoint belongs to one body, where a mask or box may also hold whoever stands in
// front or behind (two people the segmentation merged, a chair a person sits on).
#include <vector>

#include <opencv2/core.hpp>

#include "pf2/detection/human_detector.h"

namespace pf2 {

// Median of depth (CV_32F, metres; pixel (0, 0) lies at image pixel `origin`) under the keypoints
// with score >= min_score whose depth is measured (> 0) and below max_depth; 0 when fewer than
// min_count (>= 1) keypoints have one. Thread safe.
double medianDepthAtKeypoints(const cv::Mat& depth, const cv::Point& origin, const std::vector<Keypoint2d>& keypoints,
                              double min_score, int min_count, double max_depth);

}  // namespace pf2
