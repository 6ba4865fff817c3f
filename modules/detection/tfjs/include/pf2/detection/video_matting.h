#pragma once
// Robust Video Matting (Lin, Yang, Saleemi, Sengupta: "Robust High-Resolution Video Matting with
// Temporal Guidance", WACV 2022; MobileNetV3 encoder, recurrent ConvGRU decoder), the `rvm` graph
// of the human-models package, run by OpenCV DNN. Per frame it gives every person's alpha matte;
// its recurrent state carries what it saw in the frames before.
//
// Why it is here: against pf2_synth's ground-truth masks it finds 98 % of the people's depth
// pixels while marking under 1 % of the static ones, where the selfie segmenter misses seated
// people behind others and spreads onto their chairs (docs/learned_detection.md, "Video
// matting"). The `learned` detector uses it with Options::segmenter "rvm" (not the default: it
// costs about 8 times the selfie network's time).
//
// The graph is imported for one input size without its downsampling and refinement branches
// (TF.js control flow OpenCV cannot run): the frame is resized to that size instead, and the
// shape arithmetic of its decoder, computed at run time in TF.js, is bypassed because at that
// size every crop and broadcast it guards is the identity.
#include <memory>
#include <string>

#include <opencv2/core.hpp>

namespace pf2 {

class VideoMatting {
 public:
  struct Options {
    std::string model_json;  // empty: humanModelPath("rvm")
    int input_width = 320;   // network input in pixels, a multiple of 16 (the encoder's stride)
    int input_height = 240;
    // Extra passes over the first frame after construction or reset(), [0, 10]. The recurrent
    // state starts at zero, and from zero the first matte misses people the network finds once its
    // state has seen them: with the cold matte pf2_slam removed none of the people in frame 0 of
    // pf2_synth static and halfsphere (seed 1), a few frames later almost all; on the first frame
    // of the test's sequence the matte covers 74 % of the people cold and 81 % warmed up. Each
    // pass costs one frame's time.
    int warmup_passes = 3;
  };

  // Loads the model. Throws pf2::Error naming the file (missing, malformed, not importable) or the
  // option out of range.
  explicit VideoMatting(const Options& options);
  ~VideoMatting();

  // The alpha matte of a BGR frame (CV_8UC3), CV_32F in [0, 1] at the frame's size (bilinear from
  // the network's size). Feeds the recurrent state forward: call it on consecutive frames (the
  // first one after construction or reset() takes 1 + Options::warmup_passes passes). Throws
  // pf2::Error on an empty or non-BGR image. NOT thread safe.
  cv::Mat alpha(const cv::Mat& bgr);
  // Forgets the frames before (a cut in the video). NOT thread safe.
  void reset();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pf2
