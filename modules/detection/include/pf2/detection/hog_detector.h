#pragma once
// "hog" backend: OpenCV's built-in Dalal-Triggs people detector
// (cv::HOGDescriptor::getDefaultPeopleDetector, 64x128 window); needs no model files.
#include <memory>
#include <string>

#include "pf2/detection/human_detector.h"

namespace pf2 {

class HogDetector : public HumanDetector {
 public:
  struct Options {
    double image_scale = 1.0;    // the colour image is resized by this before detection (speed)
    double hit_threshold = 0.0;  // SVM margin a window needs to count
    int win_stride = 8;          // pixels between windows
    double pyramid_scale = 1.05; // factor between pyramid levels
    double nms_iou = 0.4;        // boxes overlapping a better one more than this are dropped
    double score_gain = 1.5;     // score = 1 / (1 + exp(-score_gain * svm_margin)): margin 0 -> 0.5
  };
  HogDetector() : HogDetector(Options()) {}
  explicit HogDetector(const Options& options);
  ~HogDetector() override;

  std::string name() const override { return "hog"; }
  // Person boxes in the frame's pixels. NOT thread safe.
  Detections detect(const Frame& frame) override;

 private:
  struct Impl;
  Options options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pf2
