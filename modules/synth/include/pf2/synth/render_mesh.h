#pragma once
// A triangle mesh as the synthetic renderer draws it: world-frame geometry plus either a texture
// (per-vertex texel coordinates, one texture per triangle) or per-vertex colours, and the label
// its pixels get in the label image.
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace pf2 {

struct RenderMesh {
  std::vector<Eigen::Vector3f> vertices;   // world frame, metres
  std::vector<Eigen::Vector3i> triangles;  // counter-clockwise seen from the front side
  std::vector<Eigen::Vector3f> normals;    // per vertex, unit, world frame, pointing to the front
  // Textured appearance: texel coordinates per vertex and a texture index per triangle (into the
  // texture list handed to the rasteriser). Leave both empty for per-vertex colours.
  std::vector<Eigen::Vector2f> uvs;
  std::vector<int> triangle_textures;
  std::vector<Eigen::Vector3f> colors;  // per vertex, BGR in [0, 1] (when untextured)
  std::uint16_t label = 0;              // label image value of its pixels: 0 static, k person k
  bool cull_back_faces = true;          // closed or one-sided surfaces: skip triangles seen from behind

  // Area-weighted vertex normals from the triangles (for meshes that are re-posed every frame).
  void computeVertexNormals();
};

// Textures are CV_8UC3 BGR images; texel (u, v) is column u, row v, texel centres at integers.
using TextureList = std::vector<cv::Mat>;

}  // namespace pf2
