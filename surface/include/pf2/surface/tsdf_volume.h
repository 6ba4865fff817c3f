#pragma once
// Truncated signed distance function on a sparse hash of 8x8x8 voxel blocks (1 cm voxels by
// default), fused from human-free depth with colour. Projective integration: every pixel's depth
// allocates the blocks along the truncation band of its ray, then each touched block's voxels are
// projected into the image and averaged in (weight 1 per observation). integrate() and
// deintegrate() with the same images and pose are exact inverses of the weighted average (up to
// float rounding), so a keyframe can be taken out and put back at a corrected pose (BundleFusion).
//
// Voxel v (integer coordinates) has its centre at v * voxel_size in the world frame; block b holds
// voxels 8 b .. 8 b + 7 on each axis.
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"
#include "pf2/surface/triangle_mesh.h"

namespace pf2 {

class TsdfVolume {
 public:
  struct Options {
    double voxel_size = 0.01;    // voxel edge, metres
    double truncation = 0.04;    // band half-width around the surface, metres
    double min_depth = 0.1;      // closer measurements are ignored, metres
    double max_depth = 3.5;      // farther measurements are ignored (Kinect noise > 1.5 cm; memory), metres
    int allocation_stride = 2;   // every n-th pixel (both axes) allocates blocks, pixels
    int num_threads = 2;         // threads for the per-block voxel updates and meshing
    float mesh_min_weight = 1.f; // voxels with less weight are not meshed (observations)
  };

  static constexpr int kBlockSide = 8;
  static constexpr int kBlockVoxels = kBlockSide * kBlockSide * kBlockSide;

  struct Voxel {
    float tsdf = 0.f;                 // signed distance / truncation, in [-1, 1]; > 0 in front
    float weight = 0.f;               // number of observations averaged in
    float r = 0.f, g = 0.f, b = 0.f;  // colour average, 0..255
  };
  struct Block {
    std::array<Voxel, kBlockVoxels> voxels;  // index x + 8 y + 64 z
  };
  struct IndexHash {
    std::size_t operator()(const Eigen::Vector3i& i) const {
      return (static_cast<std::size_t>(i.x()) * 73856093u) ^
             (static_cast<std::size_t>(i.y()) * 19349669u) ^
             (static_cast<std::size_t>(i.z()) * 83492791u);
    }
  };
  using BlockMap = std::unordered_map<Eigen::Vector3i, std::unique_ptr<Block>, IndexHash>;

  TsdfVolume() : TsdfVolume(Options()) {}
  // Throws pf2::Error on a non-positive voxel size or truncation.
  explicit TsdfVolume(const Options& options);

  // Fuses depth (CV_32F metres, 0 = none) seen from T_w_c; bgr (CV_8UC3, same size) may be empty
  // (colour is then left untouched). Throws pf2::Error on a size or type mismatch. NOT thread safe.
  void integrate(const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& K,
                 const Eigen::Isometry3d& T_w_c);
  // Removes exactly what integrate() with the same arguments added; voxels whose weight drops to
  // zero are reset and blocks left without weight are freed. NOT thread safe.
  void deintegrate(const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& K,
                   const Eigen::Isometry3d& T_w_c);

  // Marching cubes over all blocks: vertices on the zero crossing, colours interpolated, shared
  // vertices welded. Thread safe with other const calls.
  TriangleMesh extractMesh() const;

  // Voxel holding world point p_w (nearest centre); nullptr when its block is not allocated.
  // Thread safe with other const calls.
  const Voxel* voxel(const Eigen::Vector3d& p_w) const;
  const BlockMap& blocks() const { return blocks_; }
  std::size_t blockCount() const { return blocks_.size(); }
  // Bytes held by voxel blocks and the hash table.
  std::size_t memoryBytes() const;
  // Frees blocks whose centre is farther than `distance` metres from p_w (bounded memory on long
  // runs when only the surroundings matter). Returns how many were freed. NOT thread safe.
  std::size_t removeBlocksFartherThan(const Eigen::Vector3d& p_w, double distance);
  void clear() { blocks_.clear(); }
  const Options& options() const { return options_; }

 private:
  void update(const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& K,
              const Eigen::Isometry3d& T_w_c, float sign);

  Options options_;
  BlockMap blocks_;
};

}  // namespace pf2
