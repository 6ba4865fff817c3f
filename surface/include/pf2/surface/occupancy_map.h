#pragma once
// Coloured OctoMap occupancy tree of the static scene, built from human-free depth (usually the
// keyframes', every few pixels). Each depth image is inserted as a point cloud with ray casting:
// cells between the camera and a measurement are updated as free, so where a person stood and
// later walked away the free-space updates outvote the old hits and no occupied cell remains.
// Saved as .bt (occupancy, readable by octomap::OcTree::readBinary) and .ot (with colour).
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"

namespace octomap {
class ColorOcTree;
}

namespace pf2 {

class OccupancyMap {
 public:
  struct Options {
    double resolution = 0.05;     // leaf cell edge, metres
    double max_range = 4.0;       // rays are cut here; farther points only carve free space, metres
    double min_depth = 0.1;       // closer measurements are ignored, metres
    int pixel_stride = 4;         // every n-th pixel (both axes) becomes a ray, pixels
    double probability_hit = 0.7;     // occupancy probability of a measured endpoint
    double probability_miss = 0.4;    // occupancy probability of a cell a ray passes through
    double clamping_min = 0.12;       // occupancy probabilities are clamped to [min, max], so
    double clamping_max = 0.97;       //   a few free observations can undo many hits
  };

  OccupancyMap() : OccupancyMap(Options()) {}
  // Throws pf2::Error on a non-positive resolution.
  explicit OccupancyMap(const Options& options);
  ~OccupancyMap();
  OccupancyMap(const OccupancyMap&) = delete;
  OccupancyMap& operator=(const OccupancyMap&) = delete;

  // Inserts depth (CV_32F metres, 0 = none) seen from T_w_c with ray casting; bgr (CV_8UC3, may be
  // empty) colours the hit cells. Throws pf2::Error on a size or type mismatch. NOT thread safe.
  void insert(const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& K,
              const Eigen::Isometry3d& T_w_c);
  void clear();

  // True when the cell holding p_w is known and occupied. Thread safe with other const calls.
  bool isOccupied(const Eigen::Vector3d& p_w) const;
  // Centres of the occupied leaf cells (pruned leaves expanded to the finest resolution).
  std::vector<Eigen::Vector3d> occupiedCentres() const;
  std::size_t occupiedCount() const { return occupiedCentres().size(); }
  std::size_t memoryBytes() const;

  // Occupancy-only binary tree (.bt) and full tree with colour (.ot), written atomically.
  // Throw pf2::Error naming the path. NOT thread safe (inner nodes are brought up to date).
  void saveBinary(const std::string& path);
  void saveColor(const std::string& path);

  const octomap::ColorOcTree& tree() const { return *tree_; }
  const Options& options() const { return options_; }

 private:
  Options options_;
  std::unique_ptr<octomap::ColorOcTree> tree_;
};

}  // namespace pf2
