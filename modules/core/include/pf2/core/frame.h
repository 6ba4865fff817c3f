#pragma once
// One RGB-D observation as it enters the pipeline.
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"

namespace pf2 {

struct Frame {
  double timestamp = 0.0;        // seconds (the colour image's stamp for TUM data, as TUM tools expect)
  cv::Mat rgb;                   // CV_8UC3, BGR order (OpenCV's)
  cv::Mat depth;                 // CV_32F, metres, 0 = no measurement
  CameraIntrinsics intrinsics;   // of both images (depth registered to colour)
  int index = -1;                // position in its sequence
};

}  // namespace pf2
