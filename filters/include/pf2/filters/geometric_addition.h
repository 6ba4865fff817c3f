#pragma once
// The Dual-BBox filter's geometric addition: a DynamicEvidence source (PredictedDepthEvidence:
// depth in front of a predicted static depth) marks pixels dynamic wherever it has an opinion,
// fused with the detector in both directions:
//   - a detector's candidate (Detections::candidates: a person-like region without the evidence
//     to call it a person) is removed whole when enough of it is dynamic, and stays removed while
//     it follows a confirmed region or a detected person (the prediction stops seeing a person
//     once part of them reached a keyframe);
//   - with keep_static, depth the evidence knows as static is reported so the filter can give it
//     back where only its box, ring or temporal rule took it.
// NOT thread safe (keeps the confirmed candidates of the previous frame).
#include <memory>

#include <opencv2/core.hpp>

#include "pf2/detection/human_detector.h"

namespace pf2 {

// Source of "this depth is dynamic" evidence, e.g. depth that lies in front of what the static map
// predicts for this view. The map is built later in the pipeline; it implements this interface.
class DynamicEvidence {
 public:
  virtual ~DynamicEvidence() = default;
  // CV_8U image of depth's size, 255 where the pixel is dynamic, 0 where static or unknown.
  // Called once per filtered frame; NOT required to be thread safe.
  virtual cv::Mat dynamicMask(const cv::Mat& depth) = 0;
  // CV_8U image of depth's size, 255 where the pixel is known static (the static scene was seen
  // there at this depth before), 0 where dynamic or unknown; empty when the source cannot tell.
  // Called once per filtered frame, after dynamicMask() when the filter asked for that too (it does
  // not with its geometric addition off); NOT required to be thread safe.
  virtual cv::Mat staticMask(const cv::Mat& /*depth*/) { return cv::Mat(); }
};

class GeometricAddition {
 public:
  struct Options {
    double candidate_min_dynamic = 0.3;  // a candidate at least this fraction of whose measured
                                         // pixels are dynamic is a person missed by the detector;
                                         // in [0, 1], 0 = candidates ignored
    int candidate_memory = 30;           // frames a candidate lying mostly (half its pixels) on last
                                         // frame's confirmed pixels or detected people stays
                                         // confirmed without fresh evidence, in [0, 254]
    double candidate_min_score = 0.0;    // a candidate whose score (the detector's mean mask
                                         // probability) is at least this is a person without any
                                         // evidence; in [0, 1], 0 = evidence always needed
    double candidate_min_front = 0.2;    // m: ... and whose median depth lies at least this in front
                                         // of the median depth around it (a person stands before
                                         // the background; the selfie model's false components on
                                         // walls do not), in [0, 2], 0 = no such test
    bool keep_static = false;            // report depth the evidence knows as static (knownStatic)
  };

  GeometricAddition() : GeometricAddition(Options()) {}
  explicit GeometricAddition(const Options& options) : options_(options) {}

  void setEvidence(std::shared_ptr<DynamicEvidence> evidence) { evidence_ = std::move(evidence); }
  bool hasEvidence() const { return evidence_ != nullptr; }

  // This frame's dynamic pixels (CV_8U, 255): the evidence's opinion (with evidence_dynamic; else
  // none: only sure candidates and those following confirmed pixels are confirmed) plus the whole
  // mask (dilated by mask_dilation) of each candidate confirmed. People with a score above
  // min_confidence count as confirmed for the next frame. Empty without evidence. Throws
  // pf2::Error when the evidence's mask or a candidate's mask is not CV_8U of the depth's size.
  cv::Mat dynamicMask(const cv::Mat& depth, const Detections& detections, double min_confidence, int mask_dilation,
                      bool evidence_dynamic = true);
  // Pixels the evidence knows as static and `dynamic` does not mark (CV_8U, 255); empty unless
  // keep_static is set and the evidence can tell.
  cv::Mat knownStatic(const cv::Mat& depth, const cv::Mat& dynamic);
  // Forgets the confirmed candidates (new sequence).
  void reset() { confirmed_age_.release(); }

  const Options& options() const { return options_; }
  void setOptions(const Options& options) { options_ = options; }

 private:
  void confirmCandidates(const cv::Mat& depth, const Detections& detections, double min_confidence,
                         int mask_dilation, cv::Mat* dynamic);
  bool sure(const cv::Mat& depth, const PersonDetection& candidate) const;
  int candidateAge(const cv::Mat& depth, const cv::Mat& mask, const cv::Mat& dynamic,
                   const cv::Mat& previous_age) const;

  Options options_;
  std::shared_ptr<DynamicEvidence> evidence_;
  // Per pixel, frames since the confirmed candidate covering it last had evidence of its own
  // (0 = this frame); kNotConfirmed where no candidate was confirmed.
  static constexpr int kNotConfirmed = 255;
  cv::Mat confirmed_age_;
  cv::Mat next_age_;  // working image: this frame's ages, swapped into confirmed_age_
};

}  // namespace pf2
