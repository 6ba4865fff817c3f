#include "pf2/detection/selfie_segmenter.h"

#include <algorithm>

#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"
#include "pf2/detection/learned_models.h"
#include "pf2/detection/tfjs_graph.h"

namespace pf2 {
namespace {
constexpr int kInputSize = 256;  // the model's fixed input, square
}

struct SelfieSegmenter::Impl {
  cv::dnn::Net net;
};

SelfieSegmenter::SelfieSegmenter(const Options& options) : options_(options), impl_(std::make_unique<Impl>()) {
  if (options_.model_json.empty()) options_.model_json = humanModelPath("selfie");
  impl_->net = TfjsGraph(options_.model_json).loadNet({});
}

SelfieSegmenter::~SelfieSegmenter() = default;

cv::Mat SelfieSegmenter::run(const cv::Mat& bgr) {
  // The model takes RGB in [0, 1] at 256x256.
  const cv::Mat blob =
      cv::dnn::blobFromImage(bgr, 1.0 / 255.0, cv::Size(kInputSize, kInputSize), cv::Scalar(), true, false);
  impl_->net.setInput(blob);
  const cv::Mat out = impl_->net.forward();
  if (out.total() != static_cast<size_t>(kInputSize * kInputSize))
    throw Error("selfie: unexpected network output size");
  const cv::Mat small(kInputSize, kInputSize, CV_32F, const_cast<float*>(out.ptr<float>()));
  cv::Mat full;
  cv::resize(small, full, bgr.size(), 0, 0, cv::INTER_LINEAR);
  return full;
}

cv::Mat SelfieSegmenter::probability(const cv::Mat& bgr) {
  if (bgr.empty() || bgr.type() != CV_8UC3) throw Error("selfie: expected a non-empty 8-bit BGR image");
  if (!options_.square_crops || bgr.rows == bgr.cols) return run(bgr);
  const int side = std::min(bgr.rows, bgr.cols);
  const cv::Point far_end = bgr.cols > bgr.rows ? cv::Point(bgr.cols - side, 0) : cv::Point(0, bgr.rows - side);
  cv::Mat sum(bgr.size(), CV_32F, cv::Scalar(0)), count(bgr.size(), CV_32F, cv::Scalar(0));
  for (const cv::Point& corner : {cv::Point(0, 0), far_end}) {
    const cv::Rect crop(corner, cv::Size(side, side));
    sum(crop) += run(bgr(crop));
    count(crop) += 1.0;
  }
  return sum / count;
}

std::vector<PersonDetection> SelfieSegmenter::components(const cv::Mat& probability) const {
  return maskComponents(probability, options_);
}

std::vector<PersonDetection> maskComponents(const cv::Mat& probability, const SelfieSegmenter::Options& options) {
  const cv::Mat mask = probability > options.mask_threshold;
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids, 8, CV_32S);
  const double min_area = options.min_area_fraction * probability.total();
  std::vector<PersonDetection> people;
  for (int i = 1; i < n; ++i) {
    if (stats.at<int>(i, cv::CC_STAT_AREA) < min_area) continue;
    PersonDetection p;
    const int x = stats.at<int>(i, cv::CC_STAT_LEFT), y = stats.at<int>(i, cv::CC_STAT_TOP);
    p.box = {static_cast<float>(x), static_cast<float>(y),
             static_cast<float>(x + stats.at<int>(i, cv::CC_STAT_WIDTH)),
             static_cast<float>(y + stats.at<int>(i, cv::CC_STAT_HEIGHT))};
    p.mask = labels == i;
    p.score = static_cast<float>(cv::mean(probability, p.mask)[0]);
    if (p.score < options.min_score) continue;
    people.push_back(std::move(p));
  }
  return people;
}

Detections SelfieSegmenter::detect(const Frame& frame) {
  Detections d;
  d.timestamp = frame.timestamp;
  d.people = components(probability(frame.rgb));
  return d;
}

}  // namespace pf2
