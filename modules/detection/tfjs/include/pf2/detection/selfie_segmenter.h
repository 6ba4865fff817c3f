#pragma once
// "selfie": MediaPipe's selfie segmentation (256x256, MobileNetV3-like) run by OpenCV DNN from
// its TF.js graph. Gives a person probability per pixel; people are the connected components of
// the thresholded mask. Limits: one mask for all people, so people who touch or overlap in the
// image come out as one detection; objects next to a person (the chair on the walking_xyz test
// frame) tend to be included, and some objects alone are read as people (see min_score). It cannot
// tell "no person": made for selfies, it marks blurred or plain scenes as a person (on 69 of 120
// frames of TUM fr1/rpy, which has no people, often the whole image). Use "learned", which keeps a
// mask only under a MoveNet pose, where people may be absent.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "pf2/detection/human_detector.h"

namespace pf2 {

class SelfieSegmenter : public HumanDetector {
 public:
  struct Options {
    std::string model_json;           // TF.js model.json; empty = humanModelPath("selfie")
    float mask_threshold = 0.5f;      // probability above which a pixel belongs to a person
    double min_area_fraction = 0.01;  // components smaller than this fraction of the image are dropped
    // Components whose mean probability is lower are dropped. People on the real test frame score
    // 0.93; the model's false positives on TUM fr1/desk (a book) score 0.62-0.63.
    float min_score = 0.7f;
    // false: the whole frame is stretched to the square input (one run). true: two square crops at
    // both ends of the longer side, probabilities averaged where they overlap (two runs, no aspect
    // distortion, finer input; mask IoU 0.81 instead of 0.77 on the real test frame).
    bool square_crops = false;
  };

  // Loads the model. Throws pf2::Error naming the file if it is missing or cannot be imported.
  explicit SelfieSegmenter(const Options& options);
  ~SelfieSegmenter() override;

  std::string name() const override { return "selfie"; }
  // One detection per mask component. NOT thread safe (the network keeps buffers).
  Detections detect(const Frame& frame) override;

  // Person probability of each pixel of a BGR image, CV_32F in [0, 1], same size. NOT thread safe.
  cv::Mat probability(const cv::Mat& bgr);
  // maskComponents(probability, options). Thread safe.
  std::vector<PersonDetection> components(const cv::Mat& probability) const;

 private:
  // One network run on the whole of bgr (stretched), probability at bgr's size.
  cv::Mat run(const cv::Mat& bgr);

  struct Impl;
  Options options_;
  std::unique_ptr<Impl> impl_;
};

// Connected components (8-neighbour) of probability > options.mask_threshold, each above the
// minimum area and score, as detections: box, mask and score = mean probability inside. Any
// person probability image will do (the selfie network's, a video matte). Thread safe.
std::vector<PersonDetection> maskComponents(const cv::Mat& probability, const SelfieSegmenter::Options& options);

}  // namespace pf2
