#pragma once
// What a structured-light Kinect does to a perfect depth image, so that methods tuned on the
// synthetic sequences meet the same trouble as on TUM data:
// - nothing outside [min_depth, max_depth];
// - axial noise sigma(z) = 0.0012 + 0.0019 (z - 0.4)^2 m (Nguyen, Izadi, Lovell: "Modeling Kinect
//   sensor noise for improved 3D reconstruction and tracking", 3DIMPVT 2012);
// - disparity quantisation: z is measured as disparity d = fx b / z in steps of 1/8 pixel;
// - holes: mixed pixels along depth edges are dropped at random, and surfaces the IR projector
//   (baseline b to the right of the camera) cannot see behind a foreground edge get no depth;
// - optional colour/depth misalignment: the depth image shifted by a few pixels.
#include <cstdint>

#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"

namespace pf2 {

class DepthSensorModel {
 public:
  struct Options {
    double min_depth = 0.4;               // metres; closer surfaces read 0
    double max_depth = 4.5;               // metres; farther surfaces read 0
    bool noise = true;                    // false: exact depth, only the range limits apply
    double sigma_constant = 0.0012;       // metres (Nguyen et al. 2012)
    double sigma_quadratic = 0.0019;      // metres per square metre beyond sigma_offset
    double sigma_offset = 0.4;            // metres
    double baseline = 0.075;              // projector to IR camera, metres (Kinect v1)
    double disparity_step = 0.125;        // disparity resolution, pixels
    double edge_relative_jump = 0.04;     // a neighbour this much (times z) nearer/farther = edge
    double edge_drop_probability = 0.6;   // chance an edge pixel has no depth
    bool projector_shadows = true;        // drop surfaces the projector cannot see
    int misalign_px = 0;                  // depth shifted right by this many pixels (left if < 0)
  };

  DepthSensorModel() = default;
  explicit DepthSensorModel(const Options& options);
  const Options& options() const { return options_; }

  // The sensor's reading of the exact depth `depth` (CV_32F metres, 0 = nothing) for camera K;
  // `seed` selects the noise (same seed, same output). Thread safe (const).
  cv::Mat apply(const cv::Mat& depth, const CameraIntrinsics& K, std::uint64_t seed) const;

  // Axial noise standard deviation at depth z, metres.
  double sigma(double z) const;

 private:
  Options options_;
};

}  // namespace pf2
