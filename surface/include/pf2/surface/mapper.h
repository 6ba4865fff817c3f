#pragma once
// The static map: a TSDF surface and an OctoMap fused from the keyframes' human-free depth, kept
// correctable when the pose graph moves keyframes. Each keyframe's images are stored compressed
// (depth as 16-bit PNG at 1/5000 m, colour as JPEG) together with the pose it was last fused at;
// the volume always fuses the decoded copy, so de-integrating it later is exact (BundleFusion's
// scheme), and updateKeyframePoses() moves a keyframe by de-integrating it at the old pose and
// integrating it at the new one. The OctoMap cannot be de-integrated (its log-odds are clamped);
// it is filled when it is read (export) or when a keyframe's images are about to be dropped,
// since a pose update would only have it rebuilt from the stored keyframes then: on a run whose
// poses the back end corrects, every insertion made before the correction was wasted work.
//
// Bounded memory on long runs: `max_stored_keyframes` keeps only the newest keyframes' images
// (older keyframes stay fused but are frozen), and `keep_radius` drops TSDF blocks far from the
// current camera.
#include <cstddef>
#include <deque>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"
#include "pf2/surface/occupancy_map.h"
#include "pf2/surface/tsdf_volume.h"

namespace pf2 {

class Mapper {
 public:
  struct Options {
    TsdfVolume::Options tsdf;
    OccupancyMap::Options occupancy;
    bool build_occupancy = true;           // also keep the OctoMap
    double moved_translation = 0.001;      // keyframes moved less than this are left alone, metres
    double moved_rotation = 0.001;         // ... and turned less than this, radians
    int max_stored_keyframes = 0;          // images kept for re-integration (0 = all keyframes)
    double keep_radius = 0.0;              // TSDF blocks farther from the newest keyframe are dropped (0 = never), metres
    int depth_png_compression = 1;         // zlib level of the stored depth, 0..9
    int colour_jpeg_quality = 90;          // JPEG quality of the stored colour, 1..100
  };

  // Which files exportMap() writes into its directory.
  struct ExportOptions {
    bool mesh_ply = true;        // map.ply: coloured triangle mesh, metres, world frame
    bool octomap_bt = true;      // map.bt: occupancy tree (needs build_occupancy)
    bool octomap_ot = true;      // map.ot: occupancy tree with colour (needs build_occupancy)
    bool points_pcd = false;     // map.pcd: the mesh's vertices as coloured points
    bool mesh_obj = false;       // map.obj: the mesh as Wavefront OBJ (vertex colours)
  };

  Mapper() : Mapper(Options()) {}
  explicit Mapper(const Options& options);

  // Fuses keyframe `id` at T_w_c. depth: CV_32F metres, human-free (0 = none); bgr: CV_8UC3 or
  // empty. Throws pf2::Error when the id was added before or the images do not fit K. NOT thread safe.
  void addKeyframe(int id, const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& K,
                   const Eigen::Isometry3d& T_w_c);
  // Re-fuses every stored keyframe whose new pose differs from the one it was fused at; ids not
  // stored (unknown or frozen) are skipped. Returns how many keyframes moved. NOT thread safe.
  int updateKeyframePoses(const std::map<int, Eigen::Isometry3d>& T_w_c_by_id);

  const TsdfVolume& tsdf() const { return tsdf_; }
  // The OctoMap of the keyframes at their current poses: the pending keyframes inserted, or the
  // whole map rebuilt from the stored keyframes when keyframes moved. NOT thread safe.
  OccupancyMap& occupancy();
  TriangleMesh extractMesh() const { return tsdf_.extractMesh(); }

  std::size_t keyframeCount() const { return keyframes_.size(); }  // stored (movable) keyframes
  // The stored keyframe the next addKeyframe() drops (max_stored_keyframes reached), or -1.
  int nextToDrop() const;
  // Keyframes re-fused by updateKeyframePoses() so far.
  int refusions() const { return refusions_; }
  // The pose keyframe `id` is fused at; false when it is not stored.
  bool keyframePose(int id, Eigen::Isometry3d* T_w_c) const;
  // Bytes of the stored keyframe images, the TSDF blocks and the OctoMap as filled so far.
  std::size_t memoryBytes() const;

  // Writes the chosen files into `directory` (which must exist), each atomically. Throws
  // pf2::Error naming the file that could not be written. NOT thread safe.
  void exportMap(const std::string& directory, const ExportOptions& what);
  void exportMap(const std::string& directory) { exportMap(directory, ExportOptions()); }
  // The same with the mesh already extracted (extractMesh()), for a caller that needs it too.
  void exportMap(const std::string& directory, const ExportOptions& what, const TriangleMesh& mesh);

 private:
  struct Keyframe {
    std::vector<unsigned char> depth_png;
    std::vector<unsigned char> colour_jpeg;  // empty when the keyframe had no colour
    CameraIntrinsics K;
    Eigen::Isometry3d T_w_c;                 // the pose it is fused at
  };
  void decode(const Keyframe& keyframe, cv::Mat* depth, cv::Mat* bgr) const;
  void insertIntoOccupancy(const Keyframe& keyframe);

  Options options_;
  TsdfVolume tsdf_;
  OccupancyMap occupancy_;
  bool occupancy_stale_ = false;         // keyframes moved: the OctoMap must be rebuilt
  std::deque<int> occupancy_pending_;    // stored keyframes not in the OctoMap yet (not stale), oldest first
  std::map<int, Keyframe> keyframes_;
  std::deque<int> order_;  // stored ids, oldest first
  int refusions_ = 0;
};

// The mesh's vertices as coloured points (pcl::PointXYZRGB), binary PCD, written atomically.
// Throws pf2::Error naming the path.
void saveMeshVerticesPcd(const TriangleMesh& mesh, const std::string& path);

}  // namespace pf2
