#include "pf2/detection/keypoint_depth.h"

#include "pf2/core/median.h"

namespace pf2 {

double medianDepthAtKeypoints(const cv::Mat& depth, const cv::Point& origin, const std::vector<Keypoint2d>& keypoints,
                              double min_score, int min_count, double max_depth) {
  if (depth.type() != CV_32F || min_count < 1) return 0.0;
  std::vector<float> depths;
  for (const Keypoint2d& k : keypoints) {
    const int u = cvRound(k.u) - origin.x, v = cvRound(k.v) - origin.y;
    if (!(k.score >= min_score) || u < 0 || v < 0 || u >= depth.cols || v >= depth.rows) continue;
    const float d = depth.at<float>(v, u);
    if (d > 0.f && d < max_depth) depths.push_back(d);
  }
  if (static_cast<int>(depths.size()) < min_count) return 0.0;
  return upperMedian(&depths);
}

}  // namespace pf2
