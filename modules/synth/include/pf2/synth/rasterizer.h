#pragma once
// CPU z-buffer rasteriser for the synthetic sequences: colour (Lambert + ambient under one point
// light), depth (camera z, metres) and a label image, all from the same z-buffer, so that every
// depth pixel's label and surface are exact. Pixel (u, v) samples the ray through the continuous
// image point (u, v), the convention of CameraIntrinsics::project/backProject.
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"
#include "pf2/synth/render_mesh.h"

namespace pf2 {

struct RenderedImages {
  cv::Mat bgr;     // CV_8UC3
  cv::Mat depth;   // CV_32F, camera z in metres, 0 where no surface
  cv::Mat labels;  // CV_16U, RenderMesh::label of the visible surface (0 where none)
};

class Rasterizer {
 public:
  struct Options {
    Eigen::Vector3d light_position_w{3.0, 2.2, 2.8};  // point light, world frame, metres
    double ambient = 0.38;                            // ambient share of the albedo, [0, 1]
    double diffuse = 0.72;                            // Lambert share of the albedo, [0, 1]
    double near_plane = 0.05;                         // triangles are clipped at this camera z, metres
    int bands = 24;                                   // horizontal image bands rendered in parallel
    bool parallel = true;                             // render the bands on all hardware threads
  };

  Rasterizer() = default;
  explicit Rasterizer(const Options& options) : options_(options) {}
  const Options& options() const { return options_; }

  // Draws the meshes seen from T_w_c with intrinsics K (image size from K). Thread safe (const).
  void render(const std::vector<const RenderMesh*>& meshes, const TextureList& textures,
              const CameraIntrinsics& K, const Eigen::Isometry3d& T_w_c, RenderedImages* out) const;

  // Number of pixels the mesh alone would cover on an unbounded image plane of camera K at T_w_c
  // (no occlusion by anything else, no image border), estimated on every `stride`-th pixel of the
  // plane region within `margin` image sizes around the image. Thread safe (const).
  double unboundedCoverage(const RenderMesh& mesh, const CameraIntrinsics& K,
                           const Eigen::Isometry3d& T_w_c, int stride = 2, int margin = 2) const;

 private:
  Options options_;
};

}  // namespace pf2
