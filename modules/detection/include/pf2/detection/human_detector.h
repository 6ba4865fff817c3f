#pragma once
// What every person detector gives the rest of the pipeline. Nothing downstream knows which
// backend ran (DESIGN.md): the filter, the trackers and the body fitter read only these structs.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "pf2/core/frame.h"

namespace pf2 {

// Axis-aligned box in pixels, corners as in the paper: (x_ul, y_ul) upper left, (x_lr, y_lr)
// lower right, both inclusive-exclusive like cv::Rect (x_ul <= u < x_lr).
struct PersonBox {
  float x_ul = 0, y_ul = 0, x_lr = 0, y_lr = 0;
  float width() const { return x_lr - x_ul; }
  float height() const { return y_lr - y_ul; }
  bool empty() const { return !(x_lr > x_ul && y_lr > y_ul); }
};

// 2D keypoint in pixels with the backend's confidence (COCO-17 order where the backend has one).
struct Keypoint2d {
  float u = 0, v = 0, score = 0;
};

struct PersonDetection {
  PersonBox box;
  float score = 0;                     // detector confidence in [0, 1]
  cv::Mat mask;                        // CV_8U image-sized, 255 = this person; empty if none
  std::vector<Keypoint2d> keypoints;   // empty if the backend has none
};

struct Detections {
  double timestamp = 0;
  std::vector<PersonDetection> people;
  // Person-like regions (each with a mask) the backend saw without the evidence to call them
  // people, e.g. a segmentation component no confident pose touches (a person cut by the border,
  // blurred or too close for the pose network). Not people: a later stage may confirm them with
  // evidence of its own (the filter's geometric addition: depth in front of the static scene).
  std::vector<PersonDetection> candidates;
};

class HumanDetector {
 public:
  virtual ~HumanDetector() = default;
  // The backend's name as used on the command line ("gt", "hog", "yolo", "file", "selfie", ...).
  virtual std::string name() const = 0;
  // Detects the people in a frame. NOT thread safe (backends keep network state and history).
  virtual Detections detect(const Frame& frame) = 0;
};

}  // namespace pf2
