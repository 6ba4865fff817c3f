#pragma once
// What a person looks like, for telling people apart when they come back into view: a colour
// histogram of their pixels (HSV, 8 hue x 3 saturation x 3 value bins, summing to 1), and the
// Bhattacharyya coefficient between two such histograms (1 = the same colours, 0 = none shared).
#include <vector>

#include <opencv2/core.hpp>

namespace pf2 {

using PersonAppearance = std::vector<float>;  // empty = unknown

// The histogram of bgr's pixels inside `area` where mask (area-sized CV_8U) is non-zero; empty when
// fewer than 50 pixels. bgr: CV_8UC3 image. Thread safe.
PersonAppearance personAppearance(const cv::Mat& bgr, const cv::Rect& area, const cv::Mat& mask);

// Bhattacharyya coefficient of two histograms of the same size, in [0, 1]; 0 when either is unknown.
double appearanceSimilarity(const PersonAppearance& a, const PersonAppearance& b);

}  // namespace pf2
