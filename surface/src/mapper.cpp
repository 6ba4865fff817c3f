#include "pf2/surface/mapper.h"

#include <pcl/io/pcd_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cmath>
#include <cstdio>
#include <opencv2/imgcodecs.hpp>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"
#include "pf2/core/pose.h"

namespace pf2 {

namespace {
constexpr double kDepthScale = 5000.0;  // stored depth units per metre (the TUM PNG scale)
}

Mapper::Mapper(const Options& options)
    : options_(options), tsdf_(options.tsdf), occupancy_(options.occupancy) {}

void Mapper::decode(const Keyframe& keyframe, cv::Mat* depth, cv::Mat* bgr) const {
  const cv::Mat depth16 = cv::imdecode(keyframe.depth_png, cv::IMREAD_UNCHANGED);
  depth16.convertTo(*depth, CV_32F, 1.0 / kDepthScale);
  if (keyframe.colour_jpeg.empty()) {
    *bgr = cv::Mat();
  } else {
    *bgr = cv::imdecode(keyframe.colour_jpeg, cv::IMREAD_COLOR);
  }
}

void Mapper::addKeyframe(int id, const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& K,
                         const Eigen::Isometry3d& T_w_c) {
  if (keyframes_.count(id)) throw Error("Mapper: keyframe " + std::to_string(id) + " was added before");
  if (depth.type() != CV_32FC1 || depth.cols != K.width || depth.rows != K.height) {
    throw Error("Mapper: keyframe " + std::to_string(id) + " depth must be CV_32F of the intrinsics' size");
  }
  if (!bgr.empty() && (bgr.type() != CV_8UC3 || bgr.size() != depth.size())) {
    throw Error("Mapper: keyframe " + std::to_string(id) + " colour must be CV_8UC3 of the depth's size");
  }
  if (!T_w_c.matrix().allFinite()) throw Error("Mapper: keyframe " + std::to_string(id) + " has a non-finite pose");
  Keyframe keyframe;
  keyframe.K = K;
  keyframe.T_w_c = T_w_c;
  cv::Mat depth16;
  // Depth beyond the 16-bit range (13 m) is dropped rather than wrapped.
  cv::Mat in_range = depth.clone();
  in_range.setTo(0.f, depth > 65535.0 / kDepthScale);
  in_range.convertTo(depth16, CV_16U, kDepthScale);
  cv::imencode(".png", depth16, keyframe.depth_png, {cv::IMWRITE_PNG_COMPRESSION, options_.depth_png_compression});
  if (!bgr.empty()) {
    cv::imencode(".jpg", bgr, keyframe.colour_jpeg, {cv::IMWRITE_JPEG_QUALITY, options_.colour_jpeg_quality});
  }
  cv::Mat stored_depth, stored_bgr;
  decode(keyframe, &stored_depth, &stored_bgr);
  tsdf_.integrate(stored_depth, stored_bgr, K, T_w_c);
  if (options_.build_occupancy && !occupancy_stale_) occupancy_pending_.push_back(id);
  if (options_.keep_radius > 0) tsdf_.removeBlocksFartherThan(T_w_c.translation(), options_.keep_radius);

  keyframes_.emplace(id, std::move(keyframe));
  order_.push_back(id);
  if (options_.max_stored_keyframes > 0) {
    while (static_cast<int>(order_.size()) > options_.max_stored_keyframes) {
      // A pending keyframe goes into the OctoMap before its images go (pending is in order_'s order).
      if (!occupancy_pending_.empty() && occupancy_pending_.front() == order_.front()) {
        insertIntoOccupancy(keyframes_.at(order_.front()));
        occupancy_pending_.pop_front();
      }
      keyframes_.erase(order_.front());
      order_.pop_front();
    }
  }
}

int Mapper::updateKeyframePoses(const std::map<int, Eigen::Isometry3d>& T_w_c_by_id) {
  int moved = 0;
  for (const auto& [id, T_w_c] : T_w_c_by_id) {
    auto it = keyframes_.find(id);
    if (it == keyframes_.end() || !T_w_c.matrix().allFinite()) continue;
    Keyframe& keyframe = it->second;
    const Eigen::Isometry3d delta = keyframe.T_w_c.inverse() * T_w_c;
    if (delta.translation().norm() < options_.moved_translation &&
        rotationAngle(delta.linear()) < options_.moved_rotation) {
      continue;
    }
    cv::Mat depth, bgr;
    decode(keyframe, &depth, &bgr);
    tsdf_.deintegrate(depth, bgr, keyframe.K, keyframe.T_w_c);
    tsdf_.integrate(depth, bgr, keyframe.K, T_w_c);
    keyframe.T_w_c = T_w_c;
    ++moved;
  }
  refusions_ += moved;
  if (moved > 0 && options_.build_occupancy) {
    occupancy_stale_ = true;
    occupancy_pending_.clear();
  }
  return moved;
}

int Mapper::nextToDrop() const {
  const bool full = options_.max_stored_keyframes > 0 && static_cast<int>(order_.size()) >= options_.max_stored_keyframes;
  return full ? order_.front() : -1;
}

void Mapper::insertIntoOccupancy(const Keyframe& keyframe) {
  cv::Mat depth, bgr;
  decode(keyframe, &depth, &bgr);
  occupancy_.insert(depth, bgr, keyframe.K, keyframe.T_w_c);
}

OccupancyMap& Mapper::occupancy() {
  if (occupancy_stale_) {
    occupancy_.clear();
    occupancy_pending_.assign(order_.begin(), order_.end());
    occupancy_stale_ = false;
  }
  for (int id : occupancy_pending_) insertIntoOccupancy(keyframes_.at(id));
  occupancy_pending_.clear();
  return occupancy_;
}

bool Mapper::keyframePose(int id, Eigen::Isometry3d* T_w_c) const {
  const auto it = keyframes_.find(id);
  if (it == keyframes_.end()) return false;
  *T_w_c = it->second.T_w_c;
  return true;
}

std::size_t Mapper::memoryBytes() const {
  std::size_t bytes = tsdf_.memoryBytes() + occupancy_.memoryBytes();
  for (const auto& entry : keyframes_) {
    bytes += sizeof(Keyframe) + entry.second.depth_png.capacity() + entry.second.colour_jpeg.capacity();
  }
  return bytes;
}

void Mapper::exportMap(const std::string& directory, const ExportOptions& what) {
  const bool mesh_needed = what.mesh_ply || what.points_pcd || what.mesh_obj;
  exportMap(directory, what, mesh_needed ? extractMesh() : TriangleMesh());
}

void Mapper::exportMap(const std::string& directory, const ExportOptions& what, const TriangleMesh& mesh) {
  const std::string prefix = directory.empty() ? std::string() : directory + "/";
  if (what.mesh_ply) saveMeshPly(mesh, prefix + "map.ply");
  if (what.points_pcd) saveMeshVerticesPcd(mesh, prefix + "map.pcd");
  if (what.mesh_obj) saveMeshObj(mesh, prefix + "map.obj");
  if ((what.octomap_bt || what.octomap_ot) && !options_.build_occupancy) {
    throw Error("Mapper: " + prefix + "map.bt/.ot asked for but build_occupancy is off");
  }
  if (what.octomap_bt) occupancy().saveBinary(prefix + "map.bt");
  if (what.octomap_ot) occupancy().saveColor(prefix + "map.ot");
}

void saveMeshVerticesPcd(const TriangleMesh& mesh, const std::string& path) {
  pcl::PointCloud<pcl::PointXYZRGB> cloud;
  cloud.resize(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    pcl::PointXYZRGB& p = cloud[i];
    p.getVector3fMap() = mesh.vertices[i];
    if (!mesh.colors.empty()) {
      p.r = mesh.colors[i][0];
      p.g = mesh.colors[i][1];
      p.b = mesh.colors[i][2];
    }
  }
  const std::string temporary = temporaryPathFor(path);
  bool written = false;
  try {
    written = pcl::io::savePCDFileBinary(temporary, cloud) == 0;
  } catch (const std::exception&) {
    written = false;
  }
  if (!written) {
    std::remove(temporary.c_str());
    throw fileError(path, "cannot write the point cloud");
  }
  commitTemporaryFile(temporary, path);
}

}  // namespace pf2
