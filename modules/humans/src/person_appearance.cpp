#include "pf2/humans/person_appearance.h"

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace pf2 {

PersonAppearance personAppearance(const cv::Mat& bgr, const cv::Rect& area, const cv::Mat& mask) {
  const cv::Rect inside = area & cv::Rect(0, 0, bgr.cols, bgr.rows);
  if (bgr.type() != CV_8UC3 || inside.area() == 0 || mask.size() != area.size()) return {};
  const cv::Mat mask_inside = mask(cv::Rect(inside.tl() - area.tl(), inside.size()));
  if (cv::countNonZero(mask_inside) < 50) return {};
  cv::Mat hsv;
  cv::cvtColor(bgr(inside), hsv, cv::COLOR_BGR2HSV);
  const int channels[] = {0, 1, 2};
  const int bins[] = {8, 3, 3};
  const float hue[] = {0, 180}, level[] = {0, 256};
  const float* ranges[] = {hue, level, level};
  cv::Mat histogram;
  cv::calcHist(&hsv, 1, channels, mask_inside, histogram, 3, bins, ranges);
  const double total = cv::sum(histogram)[0];
  PersonAppearance out(histogram.begin<float>(), histogram.end<float>());
  for (float& v : out) v = static_cast<float>(v / total);
  return out;
}

double appearanceSimilarity(const PersonAppearance& a, const PersonAppearance& b) {
  if (a.empty() || a.size() != b.size()) return 0.0;
  double sum = 0;
  for (size_t i = 0; i < a.size(); ++i) sum += std::sqrt(static_cast<double>(a[i]) * b[i]);
  return std::min(1.0, sum);
}

}  // namespace pf2
