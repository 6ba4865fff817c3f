#pragma once
// Depth of a fitted body from the person's depth image. The fitter's depth term reads the surface
// around a dozen keypoints (a few pixels each), and hip and shoulder keypoints often lie near the
// silhouette's edge, where a pixel of mask error reads the background: the fitted pelvis was 4-5
// cm off along the viewing ray (RMS; pf2_slam on pf2_synth with the learned detector), more than
// across it. The aligner compares the torso surface the fitted body shows the camera with the
// person's depth at the same pixels and moves the body along the ray through its pelvis by the
// difference at a quantile a little above the median, weighted by image area (robust to a
// minority of wrong points: mask bleeding onto the background, an arm in front). The torso alone,
// because it is fitted best and lies around the pelvis: with the limbs and the head, a leg or an
// arm fitted in the wrong place moves the body. See docs/body.md, "Surface alignment".
#include <vector>

#include <Eigen/Core>

#include "pf2/body/body_model.h"
#include "pf2/core/camera_intrinsics.h"

namespace pf2 {

class BodySurfaceAligner {
 public:
  struct Options {
    // A torso vertex further than occlusion_depth behind the nearest vertex in its image cell of
    // cell_px pixels is hidden (an arm in front of the torso). cell_px [1, 32] px, about the
    // spacing of the model's vertices at 3-4 m; occlusion_depth (0, 1] m.
    double cell_px = 4.0;
    double occlusion_depth = 0.05;
    // Each visible vertex is compared with the mean measured depth in its image cell of match_px
    // pixels (pf2_slam's person points come every 2nd pixel), [1, 32] px.
    double match_px = 2.0;
    // Fewer visible torso vertices with a measured depth than this = no alignment, [1, 1e6].
    int min_vertices = 40;
    // A difference (at the quantile below) beyond this (m) is not trusted (someone else's points,
    // a fit far off): the body stays, [0, 10].
    double max_shift = 0.3;
    // The weighted quantile of (measured - vertex depth) the body is moved to, (0, 1); 0.5 = the
    // median. What lies wrongly in the torso's pixels lies mostly in front of it: the arms the fit
    // placed beside the torso while they hang in front of it (a person seen from the side or
    // close), another person passing in front. On pf2_synth with the learned detector 15 % of
    // the pixels of the torso vertices the fit showed the camera were the person's arm, 6.6 cm in
    // front of the fitted surface, and the median put the body 0.5-0.6 cm nearer than the torso's
    // own pixels would (1.6 cm RMS); the 0.6 quantile was 0.3 cm beyond it (1.0-1.2 cm RMS;
    // docs/BENCHMARKS.md, "Bodies in the map").
    double quantile = 0.6;
  };

  struct Result {
    bool applied = false;
    double shift = 0;  // m the body moved along the ray through its pelvis (+ = away from the camera)
    int vertices = 0;  // visible torso vertices with a measured depth
  };

  // The model must outlive the aligner. Throws pf2::Error for options out of range.
  BodySurfaceAligner(const BodyModel& model, const Options& options);

  // Moves body_c (camera frame) along the ray through its pelvis so that the area-weighted
  // Options::quantile of (measured depth - vertex depth) over the visible torso vertices becomes
  // 0; the measured depth is that of the person's points points_c in the vertex's pixel. Leaves body_c as it was
  // when Result::applied is false. Thread safe (const).
  Result align(const std::vector<Eigen::Vector3d>& points_c, const CameraIntrinsics& intrinsics,
               BodyParameters* body_c) const;

 private:
  const BodyModel& model_;
  Options options_;
  std::vector<int> torso_;            // the torso's vertices
  std::vector<int> torso_triangles_;  // the triangles that touch one
};

}  // namespace pf2
