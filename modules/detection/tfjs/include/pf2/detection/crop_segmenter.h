#pragma once
// "Crop masks": the segmentation head of MediaPipe's BlazePose GHUM Lite (model `blazepose-lite`)
// run on a square crop around one person, as BlazePose itself runs it on the region its person
// detector found. The selfie network sees the whole frame once and was made for a person facing
// the camera: on people cut by the image border or seen whole and small it misses limbs and legs
// (on pf2_synth's hard cases its mask covers 85-90 % of the people's depth). The crop network sees
// one person at 256x256 and was trained on whole bodies; what it marks lies on people (93 % of it
// in the test on pf2_synth). It costs one network run per person, about what the selfie network
// costs on the whole frame (BM_CropSegment), so LearnedPersonDetector runs it only for people the
// selfie mask covers badly.
#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "pf2/detection/human_detector.h"

namespace pf2 {

class PersonCropSegmenter {
 public:
  struct Options {
    std::string model_json;    // TF.js model.json; empty = humanModelPath("blazepose-lite")
    // The square crop's side is (1 + margin) times the person's box's longer side, [0, 2]
    // (refinementCrop). BlazePose's own crop is 1.25 times the body's extent.
    double margin = 0.25;
    float mask_threshold = 0.5f;  // probability above which a crop pixel is the person's, in (0, 1)
    // The network's input side in pixels: 192, 224 or 256 (256 is the model's own; a multiple of
    // 32, as its five stride-2 stages and fixed-size upsamplings need). 192 takes 0.6 of 256's
    // time (BM_CropSegment), marks as much of the person in CropSegmenter's tests and removes as
    // much in pf2_slam (docs/BENCHMARKS.md, "Crop masks"); at 160 the network marks a third of
    // the person, at 128 nothing.
    int input_size = 192;
  };

  // Loads the model. Throws pf2::Error naming the file if it is missing or cannot be imported, or
  // naming the option if one is out of its range (input_size: 192, 224 or 256).
  explicit PersonCropSegmenter(const Options& options);
  ~PersonCropSegmenter();

  // The person's mask (CV_8U, 255 = person) within refinementCropPixels(box, margin), image-sized;
  // all zero for an empty box or a crop wholly outside the image. Pixels of the crop beyond the
  // image are black to the network. bgr: 8-bit BGR; anything else throws pf2::Error. NOT thread
  // safe (the network keeps buffers).
  cv::Mat segment(const cv::Mat& bgr, const PersonBox& box);

 private:
  struct Impl;
  Options options_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pf2
