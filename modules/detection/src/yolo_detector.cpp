#include "pf2/detection/yolo_detector.h"

#include <algorithm>
#include <fstream>

#include <opencv2/dnn.hpp>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

YoloCandidate candidate(float cx, float cy, float w, float h, float sx, float sy, float score) {
  YoloCandidate c;
  c.box = cv::Rect2f((cx - 0.5f * w) * sx, (cy - 0.5f * h) * sy, w * sx, h * sy);
  c.score = score;
  return c;
}

}  // namespace

std::vector<YoloCandidate> decodeYoloOutput(const cv::Mat& output, YoloLayout layout,
                                            const cv::Size& input_size, const cv::Size& image_size,
                                            float min_score, int person_class) {
  if (output.type() != CV_32F || output.empty()) throw Error("yolo: output tensor is not float");
  // Rows x columns of the tensor with its leading batch dimension of 1 dropped.
  int rows = 0, cols = 0;
  if (output.dims == 2) {
    rows = output.size[0];
    cols = output.size[1];
  } else if (output.dims == 3 && output.size[0] == 1) {
    rows = output.size[1];
    cols = output.size[2];
  } else {
    throw Error("yolo: output tensor has " + std::to_string(output.dims) + " dimensions, expected (1,) N x K");
  }
  const float* data = output.ptr<float>();
  std::vector<YoloCandidate> out;
  const float sx_in = static_cast<float>(image_size.width) / input_size.width;
  const float sy_in = static_cast<float>(image_size.height) / input_size.height;
  switch (layout) {
    case YoloLayout::kDarknet:
    case YoloLayout::kV5: {
      const int first_class = 5;
      if (cols < first_class + person_class + 1) throw Error("yolo: output rows too short for the person class");
      const bool darknet = layout == YoloLayout::kDarknet;
      const float sx = darknet ? static_cast<float>(image_size.width) : sx_in;
      const float sy = darknet ? static_cast<float>(image_size.height) : sy_in;
      for (int i = 0; i < rows; ++i) {
        const float* r = data + static_cast<size_t>(i) * cols;
        const float score = darknet ? r[first_class + person_class] : r[4] * r[first_class + person_class];
        if (score > min_score) out.push_back(candidate(r[0], r[1], r[2], r[3], sx, sy, score));
      }
      break;
    }
    case YoloLayout::kV8: {
      if (rows < 4 + person_class + 1) throw Error("yolo: output too short for the person class");
      const float* score_row = data + static_cast<size_t>(4 + person_class) * cols;
      for (int i = 0; i < cols; ++i) {
        if (score_row[i] > min_score) {
          out.push_back(candidate(data[i], data[cols + i], data[2 * cols + i], data[3 * cols + i], sx_in, sy_in,
                                  score_row[i]));
        }
      }
      break;
    }
  }
  return out;
}

std::vector<YoloCandidate> suppressNonMaxima(std::vector<YoloCandidate> candidates, float max_iou) {
  std::stable_sort(candidates.begin(), candidates.end(),
                   [](const YoloCandidate& a, const YoloCandidate& b) { return a.score > b.score; });
  std::vector<YoloCandidate> kept;
  for (const YoloCandidate& c : candidates) {
    bool suppressed = false;
    for (const YoloCandidate& k : kept) {
      const float overlap = (c.box & k.box).area();
      const float united = c.box.area() + k.box.area() - overlap;
      if (united > 0 && overlap / united > max_iou) {
        suppressed = true;
        break;
      }
    }
    if (!suppressed) kept.push_back(c);
  }
  return kept;
}

std::vector<PersonDetection> peopleFromCandidates(const std::vector<YoloCandidate>& candidates, float max_iou,
                                                  const cv::Size& image) {
  const cv::Rect2f image_rect(0, 0, static_cast<float>(image.width), static_cast<float>(image.height));
  std::vector<PersonDetection> people;
  for (const YoloCandidate& c : suppressNonMaxima(candidates, max_iou)) {
    const cv::Rect2f b = c.box & image_rect;
    if (b.empty()) continue;
    PersonDetection person;
    person.box = PersonBox{b.x, b.y, b.x + b.width, b.y + b.height};
    person.score = c.score;
    people.push_back(std::move(person));
  }
  return people;
}

struct YoloDetector::Impl {
  cv::dnn::Net net;
  std::vector<std::string> outputs;
  bool darknet = false;
};

YoloDetector::YoloDetector(const Options& options) : options_(options), impl_(new Impl) {
  if (options.model.empty()) throw Error("yolo detector: no model file given (--yolo-model)");
  if (!std::ifstream(options.model)) throw fileError(options.model, "cannot open YOLO model");
  impl_->darknet = options.layout == "darknet" || (options.layout == "auto" && endsWith(options.model, ".cfg"));
  if (options.layout != "auto" && options.layout != "darknet" && options.layout != "v5" && options.layout != "v8") {
    throw Error("yolo detector: layout must be auto, darknet, v5 or v8, not '" + options.layout + "'");
  }
  if (options.input_width <= 0 || options.input_height <= 0) throw Error("yolo detector: input size must be > 0");
  try {
    if (impl_->darknet) {
      if (!std::ifstream(options.weights)) throw fileError(options.weights, "cannot open Darknet weights");
      impl_->net = cv::dnn::readNetFromDarknet(options.model, options.weights);
    } else {
      impl_->net = cv::dnn::readNetFromONNX(options.model);
    }
  } catch (const cv::Exception& e) {
    throw fileError(options.model, std::string("OpenCV cannot load the network: ") + e.what());
  }
  if (impl_->net.empty()) throw fileError(options.model, "OpenCV loaded an empty network");
  impl_->net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  impl_->net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  impl_->outputs = impl_->net.getUnconnectedOutLayersNames();
}

YoloDetector::~YoloDetector() = default;

Detections YoloDetector::detect(const Frame& frame) {
  Detections detections;
  detections.timestamp = frame.timestamp;
  if (frame.rgb.empty()) return detections;
  const cv::Size input(options_.input_width, options_.input_height);
  impl_->net.setInput(cv::dnn::blobFromImage(frame.rgb, 1.0 / 255.0, input, cv::Scalar(), true, false));
  std::vector<cv::Mat> outputs;
  impl_->net.forward(outputs, impl_->outputs);
  std::vector<YoloCandidate> candidates;
  for (const cv::Mat& out : outputs) {
    YoloLayout layout = YoloLayout::kDarknet;
    if (!impl_->darknet) {
      if (options_.layout == "v5") layout = YoloLayout::kV5;
      else if (options_.layout == "v8") layout = YoloLayout::kV8;
      else layout = (out.dims == 3 && out.size[1] < out.size[2]) ? YoloLayout::kV8 : YoloLayout::kV5;
    }
    const auto decoded = decodeYoloOutput(out, layout, input, frame.rgb.size(),
                                          static_cast<float>(options_.confidence), options_.person_class);
    candidates.insert(candidates.end(), decoded.begin(), decoded.end());
  }
  detections.people = peopleFromCandidates(candidates, static_cast<float>(options_.nms_iou), frame.rgb.size());
  return detections;
}

}  // namespace pf2
