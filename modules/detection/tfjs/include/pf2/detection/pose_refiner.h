#pragma once
// PoseRefiner: a second, closer look at one person's keypoints. MoveNet runs on the whole frame
// at 256x192, where a person 3-4 m away is 40-60 input pixels tall and each keypoint comes from
// a 4-pixel output grid: a few image pixels of error per keypoint, which the body fitter turns
// into centimetres. The refiner runs MoveNet again on a square crop around the person, so that
// they fill the network's input, and returns the keypoints of the pose found there.
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "pf2/detection/human_detector.h"

namespace pf2 {

class MoveNetDetector;

class PoseRefiner {
 public:
  struct Options {
    int input_size = 192;   // pixels: the crop's side at the network's input, multiple of 32, [64, 512]
    double margin = 0.1;    // the crop's side is (1 + margin) times the box's longer side, [0, 2]
    double min_iou = 0.5;   // a pose found in the crop must overlap the person's box this much, [0, 1]
  };

  // Loads the MoveNet model (humanModelPath("movenet-multipose")). Throws pf2::Error when it is
  // missing or the options are out of range.
  explicit PoseRefiner(const Options& options);
  ~PoseRefiner();

  // The 17 COCO keypoints (image pixels) of the person in `box` on the BGR image, from the crop;
  // false, and *keypoints untouched, when the crop shows no pose overlapping the box by min_iou.
  // NOT thread safe (the network keeps buffers); one refiner per thread.
  bool refine(const cv::Mat& bgr, const PersonBox& box, std::vector<Keypoint2d>* keypoints);
  // The pose the crop around `box` shows that overlaps the box most (by at least min_iou), with
  // its box, keypoints and MoveNet score in image pixels; false, and *person untouched, when there
  // is none. NOT thread safe, as refine.
  bool find(const cv::Mat& bgr, const PersonBox& box, PersonDetection* person);

 private:
  Options options_;
  std::unique_ptr<MoveNetDetector> movenet_;
};

// The square crop PoseRefiner looks at for a box: centred on it, side (1 + margin) times its longer
// side, in image pixels (may reach beyond the image). Thread safe.
cv::Rect2f refinementCrop(const PersonBox& box, double margin);
// refinementCrop in whole pixels, at least 1 x 1. Thread safe.
cv::Rect refinementCropPixels(const PersonBox& box, double margin);
// The crop of a BGR image as an image of its own: pixels beyond the image's border black (as the
// networks see padding), the crop's top-left corner at (0, 0). Thread safe.
cv::Mat cropWithBlackBorder(const cv::Mat& bgr, const cv::Rect& crop);

}  // namespace pf2
