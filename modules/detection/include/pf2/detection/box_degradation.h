#pragma once
// Deliberate damage to detections, to test the filter against the paper's three failure causes
// (incomplete boxes, misaligned depth, blur) and against missed and false detections.
// Deterministic: the random draws of a frame depend only on the seed and the frame's timestamp,
// never on how many frames were processed before.
#include <cstdint>
#include <string>

#include <opencv2/core.hpp>

#include "pf2/detection/human_detector.h"

namespace pf2 {

struct BoxDegradation {
  double shrink = 0.0;               // fraction each box's width and height lose (about its centre), 0..1
  double shift = 0.0;                // pixels each box (and its mask) moves, in a random direction
  double drop_probability = 0.0;     // chance a person is not detected at all, 0..1
  double false_positive_rate = 0.0;  // mean number of false boxes added per frame (Poisson)
  uint64_t seed = 1;

  bool active() const {
    return shrink > 0 || shift > 0 || drop_probability > 0 || false_positive_rate > 0;
  }
};

class Settings;

// Binds the fields of `degradation` to `settings` under prefix + shrink, shift, drop,
// false_positives, seed (e.g. "detector.gt_" in pf2_slam, "boxes." in pf2_detect).
void declareBoxDegradationSettings(const std::string& prefix, BoxDegradation* degradation, Settings* settings);

// Applies the degradation to detections of an image of the given size. Dropped people disappear,
// surviving boxes shrink then shift (masks shift with them), false positives are person-shaped
// boxes (height 80..320 px, width 0.4 x height) with scores in (0.5, 1) and no mask. Boxes are
// clipped to the image. Thread safe.
void degradeDetections(const BoxDegradation& degradation, const cv::Size& image, Detections* detections);

}  // namespace pf2
