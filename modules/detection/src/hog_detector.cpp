#include "pf2/detection/hog_detector.h"

#include <cmath>

#include <opencv2/imgproc.hpp>
#include <opencv2/objdetect.hpp>

#include "pf2/core/error.h"
#include "pf2/detection/yolo_detector.h"

namespace pf2 {

struct HogDetector::Impl {
  cv::HOGDescriptor hog;  // default: 64x128 window, the people detector's
};

HogDetector::HogDetector(const Options& options) : options_(options), impl_(new Impl) {
  if (!(options.image_scale > 0) || options.win_stride <= 0 || !(options.pyramid_scale > 1.0)) {
    throw Error("hog detector: image_scale must be > 0, win_stride > 0 and pyramid_scale > 1");
  }
  impl_->hog.setSVMDetector(cv::HOGDescriptor::getDefaultPeopleDetector());
}

HogDetector::~HogDetector() = default;

Detections HogDetector::detect(const Frame& frame) {
  Detections detections;
  detections.timestamp = frame.timestamp;
  if (frame.rgb.empty()) return detections;
  cv::Mat image = frame.rgb;
  if (options_.image_scale != 1.0) {
    cv::resize(frame.rgb, image, cv::Size(), options_.image_scale, options_.image_scale, cv::INTER_AREA);
  }
  std::vector<cv::Rect> found;
  std::vector<double> margins;
  // No grouping inside OpenCV: its grouping drops the margins; suppressNonMaxima keeps the best window.
  impl_->hog.detectMultiScale(image, found, margins, options_.hit_threshold,
                              cv::Size(options_.win_stride, options_.win_stride), cv::Size(0, 0),
                              options_.pyramid_scale, 0.0, false);
  std::vector<YoloCandidate> candidates;
  const float back = static_cast<float>(1.0 / options_.image_scale);
  for (size_t i = 0; i < found.size(); ++i) {
    const double margin = i < margins.size() ? margins[i] : 0.0;
    YoloCandidate c;
    c.box = cv::Rect2f(found[i].x * back, found[i].y * back, found[i].width * back, found[i].height * back);
    c.score = static_cast<float>(1.0 / (1.0 + std::exp(-options_.score_gain * margin)));
    candidates.push_back(c);
  }
  detections.people = peopleFromCandidates(candidates, static_cast<float>(options_.nms_iou), frame.rgb.size());
  return detections;
}

}  // namespace pf2
