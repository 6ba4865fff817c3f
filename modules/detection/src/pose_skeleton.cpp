#include "pf2/detection/pose_skeleton.h"

#include <opencv2/imgproc.hpp>

namespace pf2 {

namespace {

// The COCO-17 keypoints, and the pairs of them joined by a limb (and the nose to each shoulder).
constexpr int kCocoKeypoints = 17;
const int kLimbs[][2] = {{5, 6}, {5, 7}, {7, 9}, {6, 8}, {8, 10}, {5, 11}, {6, 12}, {11, 12},
                         {11, 13}, {13, 15}, {12, 14}, {14, 16}, {0, 5}, {0, 6}};

}  // namespace

cv::Mat poseSkeleton(const std::vector<Keypoint2d>& k, const cv::Rect& area, double min_score, int limb_width) {
  cv::Mat skeleton = cv::Mat::zeros(area.size(), CV_8U);
  if (k.size() < static_cast<size_t>(kCocoKeypoints)) return skeleton;
  auto seen = [&](int i) { return k[i].score >= min_score; };
  auto at = [&](int i) { return cv::Point(cvRound(k[i].u) - area.x, cvRound(k[i].v) - area.y); };
  for (const auto& limb : kLimbs) {
    if (seen(limb[0]) && seen(limb[1])) cv::line(skeleton, at(limb[0]), at(limb[1]), 255, limb_width);
  }
  if (seen(5) && seen(6) && seen(11) && seen(12)) {
    const std::vector<cv::Point> torso{at(5), at(6), at(12), at(11)};
    cv::fillConvexPoly(skeleton, torso, 255);
  }
  return skeleton;
}

}  // namespace pf2
