#include "pf2/filters/geometric_addition.h"

#include <algorithm>
#include <vector>

#include "pf2/core/error.h"
#include "pf2/core/median.h"
#include "image_ops.h"

namespace pf2 {

// The filter applies the mask in its output pass; the pixels it removes keep their state (kept),
// so they are not carried to the next frame: they may be background.
cv::Mat GeometricAddition::dynamicMask(const cv::Mat& depth, const Detections& detections, double min_confidence,
                                       int mask_dilation, bool evidence_dynamic) {
  if (!evidence_) return cv::Mat();
  cv::Mat dynamic = evidence_dynamic ? evidence_->dynamicMask(depth) : cv::Mat::zeros(depth.size(), CV_8U);
  if (dynamic.size() != depth.size() || dynamic.type() != CV_8U) {
    throw Error("DualBBoxFilter: DynamicEvidence returned a mask that is not CV_8U of the depth's size");
  }
  confirmCandidates(depth, detections, min_confidence, mask_dilation, &dynamic);
  return dynamic;
}

cv::Mat GeometricAddition::knownStatic(const cv::Mat& depth, const cv::Mat& dynamic) {
  if (!options_.keep_static || !evidence_) return cv::Mat();
  cv::Mat known = evidence_->staticMask(depth);
  if (!known.empty()) known.setTo(0, dynamic);
  return known;
}

// Geometric addition, fused with the detector: a candidate region (a person-like mask the detector
// could not call a person) whose measured pixels are dynamic often enough is a person; all of its
// mask joins the dynamic pixels, also the parts the evidence cannot see (where the person stood
// still, or the prediction had no depth). A candidate lying mostly on last frame's confirmed pixels
// (or on a person the detector reported) stays confirmed without fresh evidence for up to
// candidate_memory frames: once part of a person has reached a keyframe, the prediction holds them
// and shows them as static.
void GeometricAddition::confirmCandidates(const cv::Mat& depth, const Detections& detections, double min_confidence,
                                          int mask_dilation, cv::Mat* dynamic) {
  if (!(options_.candidate_min_dynamic > 0.0)) return;
  if (confirmed_age_.size() != depth.size()) confirmed_age_ = cv::Mat(depth.size(), CV_8U, cv::Scalar(kNotConfirmed));
  // The detector's people count as confirmed too: a person it loses for a few frames (too close,
  // cut by the border) comes back as a candidate on the same pixels.
  next_age_.create(depth.size(), CV_8U);  // reused from frame to frame, like the filter's working images
  next_age_.setTo(kNotConfirmed);
  for (const PersonDetection& person : detections.people) {
    if (person.score > min_confidence && person.mask.size() == depth.size()) next_age_.setTo(0, person.mask);
  }
  for (const PersonDetection& candidate : detections.candidates) {
    if (candidate.mask.empty()) continue;
    if (candidate.mask.size() != depth.size() || candidate.mask.type() != CV_8U) {
      throw Error("DualBBoxFilter: a candidate's mask is not CV_8U of the depth's size");
    }
    cv::Rect area;
    const cv::Mat grown = dilatedOnArea(candidate.mask, mask_dilation, &area);
    if (area.empty()) continue;
    const int age = sure(depth, candidate)
                        ? 0
                        : candidateAge(depth(area), candidate.mask(area), (*dynamic)(area), confirmed_age_(area));
    if (age == kNotConfirmed) continue;
    (*dynamic)(area).setTo(255, grown);
    cv::Mat ages(area.size(), CV_8U, cv::Scalar(kNotConfirmed));
    ages.setTo(age, grown);
    cv::Mat target = next_age_(area);
    cv::min(target, ages, target);
  }
  cv::swap(confirmed_age_, next_age_);
}

namespace {

constexpr int kSurroundRadius = 15;  // pixels: the band around a candidate its depth is compared with

// Median of the measured depths (> 0) of `depth` where `mask` is set; 0 when there are none.
float medianDepth(const cv::Mat& depth, const cv::Mat& mask) {
  std::vector<float> values;
  for (int v = 0; v < depth.rows; ++v) {
    const float* d = depth.ptr<float>(v);
    const uint8_t* m = mask.ptr<uint8_t>(v);
    for (int u = 0; u < depth.cols; ++u) {
      if (m[u] && d[u] > 0.f) values.push_back(d[u]);
    }
  }
  return upperMedian(&values);
}

}  // namespace

// A candidate the detector is sure of, standing in front of what surrounds it.
bool GeometricAddition::sure(const cv::Mat& depth, const PersonDetection& candidate) const {
  if (!(options_.candidate_min_score > 0.0) || candidate.score < options_.candidate_min_score) return false;
  if (!(options_.candidate_min_front > 0.0)) return true;
  cv::Rect area;
  const cv::Mat grown = dilatedOnArea(candidate.mask, kSurroundRadius, &area);
  const cv::Mat inside = candidate.mask(area) > 0;
  const float person = medianDepth(depth(area), inside);
  const float around = medianDepth(depth(area), grown & ~inside);
  return person > 0.f && around > 0.f && around - person >= options_.candidate_min_front;
}

// 0 with fresh evidence, 1 + the youngest age under it when carried, else kNotConfirmed.
int GeometricAddition::candidateAge(const cv::Mat& depth, const cv::Mat& mask, const cv::Mat& dynamic,
                                    const cv::Mat& previous_age) const {
  const cv::Mat inside = mask > 0;
  const cv::Mat measured = inside & (depth > 0.f);
  const int total = cv::countNonZero(measured);
  if (total > 0 && cv::countNonZero(measured & (dynamic > 0)) >= options_.candidate_min_dynamic * total) return 0;
  const cv::Mat carried = inside & (previous_age < kNotConfirmed);
  if (cv::countNonZero(carried) * 2 < cv::countNonZero(inside)) return kNotConfirmed;
  double youngest = kNotConfirmed;
  cv::minMaxLoc(previous_age, &youngest, nullptr, nullptr, nullptr, carried);
  return youngest + 1 <= options_.candidate_memory ? static_cast<int>(youngest) + 1 : kNotConfirmed;
}

}  // namespace pf2
