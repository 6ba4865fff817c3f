#pragma once
// Map quality against a ground-truth static mesh: accuracy (distance of every map vertex to the
// ground truth), ghosts (map vertices far from any static surface: people fused into the map),
// and completeness (share of the ground-truth surface the camera saw that the map covers).
// Distances are exact point-to-triangle distances found through a uniform grid.
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"
#include "pf2/surface/triangle_mesh.h"

namespace pf2 {

// Distance from points to a triangle mesh, up to a cap. Thread safe (const) after construction.
class MeshDistance {
 public:
  // cell_size: grid cell edge in metres (about the triangle size works well).
  MeshDistance(const TriangleMesh& mesh, double max_distance, double cell_size = 0.02);
  // Exact distance to the nearest triangle, or max_distance when none is closer.
  double distance(const Eigen::Vector3d& p) const;
  double maxDistance() const { return max_distance_; }

 private:
  Eigen::Vector3i cellOf(const Eigen::Vector3d& p) const;
  static std::uint64_t key(const Eigen::Vector3i& cell);

  std::vector<Eigen::Vector3d> a_, b_, c_;  // triangle corners
  double max_distance_, cell_size_;
  std::unordered_map<std::uint64_t, std::vector<int>> cells_;
};

// Closest distance from p to the triangle (a, b, c), by the Voronoi region of p.
double pointTriangleDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                             const Eigen::Vector3d& c);

// Completeness of the seen samples in one bin of a breakdown.
struct CompletenessBin {
  double lower = 0.0, upper = 0.0;  // the bin's range of the breakdown's quantity
  std::size_t seen = 0, covered = 0;
};

struct MapQuality {
  std::size_t map_vertices = 0;
  double mean = 0.0, median = 0.0, p90 = 0.0, max = 0.0;  // map vertex -> ground truth, metres (capped)
  std::size_t ghost_vertices = 0;  // map vertices farther than ghost_distance from the ground truth
  std::size_t seen_samples = 0;    // ground-truth surface samples the camera saw
  double completeness = 0.0;       // share of them within completeness_distance of the map
  // Completeness by the nearest camera depth a sample was seen at (0.5 m bins), and by its most
  // frontal view's incidence angle (between the ray and the surface normal; 15 degree bins).
  std::vector<CompletenessBin> by_range, by_incidence;
};

// The breakdowns of q as text, one line per non-empty bin ("  nearest view 3.0-3.5 m: 77.6 % of N").
std::string completenessBreakdown(const MapQuality& q);

class MapEvaluator {
 public:
  struct Options {
    double max_distance = 0.10;           // distances are searched (and capped) up to this, metres
    double ghost_distance = 0.03;         // a map vertex farther than this is a ghost, metres
    double completeness_distance = 0.02;  // a ground-truth sample this close to the map is covered, metres
    double sample_spacing = 0.01;         // spacing of the ground-truth surface samples, metres
    double seen_tolerance = 0.02;         // a sample is seen when a depth pixel lies this close, metres
  };

  MapEvaluator(const TriangleMesh& ground_truth, const Options& options);
  // Marks the samples a depth image (CV_32F metres) observed: in front of the camera, projecting
  // into the image onto a pixel whose depth lies within seen_tolerance of the sample's; keeps the
  // nearest depth and the most frontal incidence each sample was seen at. NOT thread safe.
  void markSeen(const cv::Mat& depth, const CameraIntrinsics& K, const Eigen::Isometry3d& T_w_c);
  void markAllSeen();
  std::size_t sampleCount() const { return samples_.size(); }

  // Thread safe (const).
  MapQuality evaluate(const TriangleMesh& map) const;

 private:
  Options options_;
  MeshDistance ground_truth_;
  std::vector<Eigen::Vector3d> samples_;
  std::vector<Eigen::Vector3f> normals_;   // unit normal of each sample's triangle (either side)
  std::vector<char> seen_;
  std::vector<float> nearest_depth_;      // nearest camera depth the sample was seen at, metres
  std::vector<float> best_cosine_;        // |cos| of its most frontal view's incidence angle
};

}  // namespace pf2
