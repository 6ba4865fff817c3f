#include "pf2/filters/mask_metrics.h"

#include <algorithm>
#include <cmath>

#include "pf2/core/error.h"

namespace pf2 {

MaskCounts& MaskCounts::operator+=(const MaskCounts& other) {
  person += other.person;
  person_removed += other.person_removed;
  static_total += other.static_total;
  static_kept += other.static_kept;
  frames += other.frames;
  return *this;
}

MaskCounts countMaskAgreement(const cv::Mat& input_depth, const cv::Mat& static_depth,
                              const cv::Mat& person_mask) {
  if (input_depth.type() != CV_32F || static_depth.type() != CV_32F ||
      input_depth.size() != static_depth.size() || input_depth.size() != person_mask.size() ||
      (person_mask.type() != CV_8U && person_mask.type() != CV_16U)) {
    throw Error("countMaskAgreement: expected CV_32F depths and a CV_8U/CV_16U mask of one size");
  }
  cv::Mat person;
  person_mask.convertTo(person, CV_8U);  // saturates ids to 255, keeps zero as zero
  MaskCounts counts;
  counts.frames = 1;
  for (int v = 0; v < input_depth.rows; ++v) {
    const float* in = input_depth.ptr<float>(v);
    const float* out = static_depth.ptr<float>(v);
    const uint8_t* m = person.ptr<uint8_t>(v);
    for (int u = 0; u < input_depth.cols; ++u) {
      if (!(std::isfinite(in[u]) && in[u] > 0.f)) continue;
      const bool kept = std::isfinite(out[u]) && out[u] > 0.f;
      if (m[u]) {
        ++counts.person;
        if (!kept) ++counts.person_removed;
      } else {
        ++counts.static_total;
        if (kept) ++counts.static_kept;
      }
    }
  }
  return counts;
}

cv::Mat shiftMaskRight(const cv::Mat& mask, int dx) {
  if (dx == 0) return mask;
  cv::Mat out = cv::Mat::zeros(mask.size(), mask.type());
  const int width = mask.cols - std::abs(dx);
  if (width <= 0) return out;
  mask(cv::Rect(std::max(0, -dx), 0, width, mask.rows)).copyTo(out(cv::Rect(std::max(0, dx), 0, width, mask.rows)));
  return out;
}

}  // namespace pf2