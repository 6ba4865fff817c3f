#pragma once
// "movenet": Google's MoveNet MultiPose Lightning (CenterNet-style, MobileNetV2 + FPN) run by
// OpenCV DNN from its TF.js graph. Finds up to six people with a box and the 17 COCO keypoints
// (nose, eyes, ears, shoulders, elbows, wrists, hips, knees, ankles). The graph's int32 input
// cast and its ArgMax/GatherNd/TopK decoding cannot run in OpenCV, so the graph is cut after its
// normalisation and before its decoding; both are done here in C++ (same formulas as the graph).
// No masks: combine with "selfie" (LearnedPersonDetector) for those.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "pf2/detection/human_detector.h"

namespace pf2 {

class MoveNetDetector : public HumanDetector {
 public:
  struct Options {
    std::string model_json;           // TF.js model.json; empty = humanModelPath("movenet-multipose")
    int input_width = 256;            // network input in pixels, multiple of 32; 256x192 keeps 4:3
    int input_height = 192;
    float min_person_score = 0.2f;    // people below this score (centre x mean confident keypoint score) are dropped
    float keypoint_threshold = 0.127f;  // keypoints above it make the person score (the model's value)
    int max_people = 6;               // centres kept after non-maximum suppression (the model's top-k)
  };

  // Loads the model. Throws pf2::Error naming the file if it is missing or cannot be imported, or
  // if the input size is not a positive multiple of 32.
  explicit MoveNetDetector(const Options& options);
  ~MoveNetDetector() override;

  std::string name() const override { return "movenet"; }
  // Boxes and 17 keypoints per person (keypoint score 0 = not found inside the person's box).
  // NOT thread safe (the network keeps buffers).
  Detections detect(const Frame& frame) override;

 private:
  struct Impl;
  Options options_;
  std::unique_ptr<Impl> impl_;
};

// MoveNet MultiPose decoding, as the graph does it (see docs/learned_detection.md), separate so it
// can be tested without the model. heads: the six NCHW output blobs (batch 1) on the output grid,
// in this order: centre (1 channel, probability), keypoint heatmaps (17, probability), regression
// from the centre (34: dy, dx per keypoint, cells), sub-cell offsets (34: dy, dx), box size
// (2: h, w, cells), box centre offset (2: dy, dx). cell_u, cell_v: pixels per grid cell in the
// image. Throws pf2::Error on unexpected shapes. Thread safe.
std::vector<PersonDetection> decodeMoveNet(const std::vector<cv::Mat>& heads, float cell_u, float cell_v,
                                          const MoveNetDetector::Options& options);

}  // namespace pf2
