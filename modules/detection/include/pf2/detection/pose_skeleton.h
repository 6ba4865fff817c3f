#pragma once
// A person's body drawn from their COCO-17 keypoints: the limbs as thick lines and the torso
// filled. Where a person posed without a mask has their depth, a box holds the chair, the floor
// and the wall beside them as well; the skeleton holds (next to) only them.
#include <vector>

#include <opencv2/core.hpp>

#include "pf2/detection/human_detector.h"

namespace pf2 {

// A limb's width as a share of the person's box height (a forearm or shin of a standing person is
// about a tenth of their height).
constexpr double kSkeletonLimbWidthShare = 0.1;

// The skeleton of `keypoints` (image pixels) on the image pixels of `area`: CV_8U of area's size,
// 255 on each limb whose two keypoints score at least min_score (lines limb_width pixels wide,
// clipped to the area) and on the torso when both shoulders and both hips do; all 0 with fewer
// than 17 keypoints. Thread safe.
cv::Mat poseSkeleton(const std::vector<Keypoint2d>& keypoints, const cv::Rect& area, double min_score, int limb_width);

}  // namespace pf2
