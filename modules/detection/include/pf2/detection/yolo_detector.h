#pragma once
// "yolo" backend: OpenCV DNN running a YOLO network on the CPU, person class only.
// Darknet (.cfg + .weights: YOLOv4 / YOLOv4-tiny as in the paper) or ONNX (YOLOv5 export,
// output (1, N, 85); YOLOv8 export, output (1, 84, N)). Users supply the files (docs/detection.md).
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "pf2/detection/human_detector.h"

namespace pf2 {

// How a network's output rows are laid out.
enum class YoloLayout {
  kDarknet,  // OpenCV's Darknet [yolo] output: rows (cx, cy, w, h) in [0, 1] of the image,
             // objectness, 80 class scores already multiplied by objectness
  kV5,       // (1, N, 5 + classes): (cx, cy, w, h) in input pixels, objectness, class scores
  kV8,       // (1, 4 + classes, N): (cx, cy, w, h) in input pixels, class scores (no objectness)
};

struct YoloCandidate {
  cv::Rect2f box;  // image pixels
  float score = 0;
};

// Person candidates (class `person_class`) with score > min_score from one output tensor, boxes
// mapped from the network input (input_size) to the image (image_size) by plain scaling (the input
// is the image resized without letterbox). Throws pf2::Error on a tensor that does not fit the
// layout. Thread safe.
std::vector<YoloCandidate> decodeYoloOutput(const cv::Mat& output, YoloLayout layout,
                                            const cv::Size& input_size, const cv::Size& image_size,
                                            float min_score, int person_class = 0);
// Greedy non-maximum suppression: best score first, dropping boxes whose IoU with a kept box
// exceeds max_iou. Returns the kept candidates, best first. Thread safe.
std::vector<YoloCandidate> suppressNonMaxima(std::vector<YoloCandidate> candidates, float max_iou);
// suppressNonMaxima, then the kept boxes clipped to the image as people (empty ones dropped).
// Thread safe.
std::vector<PersonDetection> peopleFromCandidates(const std::vector<YoloCandidate>& candidates, float max_iou,
                                                  const cv::Size& image);

class YoloDetector : public HumanDetector {
 public:
  struct Options {
    std::string model;              // .cfg (Darknet) or .onnx
    std::string weights;            // .weights for Darknet; unused for ONNX
    std::string layout = "auto";    // auto | darknet | v5 | v8 (auto: .cfg = darknet, ONNX by shape)
    int input_width = 416;          // network input, pixels (multiple of 32; 640 for v5/v8 exports)
    int input_height = 416;
    double confidence = 0.5;        // person score must exceed this (the paper's c > 0.5)
    double nms_iou = 0.45;          // IoU above which the weaker of two boxes is dropped
    int person_class = 0;           // COCO "person"
  };
  // Loads the network; throws pf2::Error naming the file when it is missing or OpenCV rejects it.
  explicit YoloDetector(const Options& options);
  ~YoloDetector() override;

  std::string name() const override { return "yolo"; }
  // NOT thread safe (one network instance).
  Detections detect(const Frame& frame) override;

 private:
  struct Impl;
  Options options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pf2
