#include "pf2/surface/occupancy_map.h"

#include <fcntl.h>
#include <unistd.h>

#include <octomap/ColorOcTree.h>

#include <cmath>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"

namespace pf2 {

OccupancyMap::OccupancyMap(const Options& options) : options_(options) {
  if (!(options_.resolution > 0)) throw Error("OccupancyMap: resolution must be positive");
  options_.pixel_stride = std::max(1, options_.pixel_stride);
  clear();
}

OccupancyMap::~OccupancyMap() = default;

void OccupancyMap::clear() {
  tree_ = std::make_unique<octomap::ColorOcTree>(options_.resolution);
  tree_->setProbHit(options_.probability_hit);
  tree_->setProbMiss(options_.probability_miss);
  tree_->setClampingThresMin(options_.clamping_min);
  tree_->setClampingThresMax(options_.clamping_max);
}

void OccupancyMap::insert(const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& K,
                          const Eigen::Isometry3d& T_w_c) {
  if (depth.type() != CV_32FC1 || depth.cols != K.width || depth.rows != K.height) {
    throw Error("OccupancyMap: depth must be CV_32F of the intrinsics' size");
  }
  if (!bgr.empty() && (bgr.type() != CV_8UC3 || bgr.size() != depth.size())) {
    throw Error("OccupancyMap: colour must be CV_8UC3 of the depth's size");
  }
  octomap::Pointcloud cloud;
  std::vector<cv::Vec3b> colours;
  const int stride = options_.pixel_stride;
  for (int v = 0; v < depth.rows; v += stride) {
    const float* row = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; u += stride) {
      const double d = row[u];
      if (!(d >= options_.min_depth) || !std::isfinite(d)) continue;
      const Eigen::Vector3d p_w = T_w_c * K.backProject(u, v, d);
      cloud.push_back(static_cast<float>(p_w.x()), static_cast<float>(p_w.y()), static_cast<float>(p_w.z()));
      colours.push_back(bgr.empty() ? cv::Vec3b(255, 255, 255) : bgr.ptr<cv::Vec3b>(v)[u]);
    }
  }
  const Eigen::Vector3d& o = T_w_c.translation();
  const octomap::point3d origin(static_cast<float>(o.x()), static_cast<float>(o.y()), static_cast<float>(o.z()));
  // discretize: one ray per end cell, which is what makes dense depth affordable.
  tree_->insertPointCloud(cloud, origin, options_.max_range, false, true);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const octomap::point3d& p = cloud[i];
    if ((p - origin).norm() > options_.max_range) continue;
    tree_->integrateNodeColor(p.x(), p.y(), p.z(), colours[i][2], colours[i][1], colours[i][0]);
  }
}

bool OccupancyMap::isOccupied(const Eigen::Vector3d& p_w) const {
  const octomap::ColorOcTreeNode* node = tree_->search(p_w.x(), p_w.y(), p_w.z());
  return node && tree_->isNodeOccupied(node);
}

std::vector<Eigen::Vector3d> OccupancyMap::occupiedCentres() const {
  std::vector<Eigen::Vector3d> centres;
  for (auto it = tree_->begin_leafs(), end = tree_->end_leafs(); it != end; ++it) {
    if (!tree_->isNodeOccupied(*it)) continue;
    const double size = it.getSize();
    const int n = static_cast<int>(std::lround(size / options_.resolution));
    const Eigen::Vector3d corner = Eigen::Vector3d(it.getX(), it.getY(), it.getZ()) -
                                   Eigen::Vector3d::Constant(0.5 * size - 0.5 * options_.resolution);
    for (int x = 0; x < n; ++x) {
      for (int y = 0; y < n; ++y) {
        for (int z = 0; z < n; ++z) centres.push_back(corner + options_.resolution * Eigen::Vector3d(x, y, z));
      }
    }
  }
  return centres;
}

std::size_t OccupancyMap::memoryBytes() const { return tree_->memoryUsage(); }

namespace {

// OctoMap's binary writer reports "Writing N nodes to output stream... done." on stderr; a
// program's stderr is for its progress and its one error line. Standard error is pointed at
// /dev/null while the tree is written (only the map export writes, after the run's threads
// stopped) and restored after, also when the writer throws.
class QuietStderr {
 public:
  QuietStderr() : saved_(::dup(STDERR_FILENO)) {
    const int null = ::open("/dev/null", O_WRONLY);
    if (saved_ >= 0 && null >= 0) ::dup2(null, STDERR_FILENO);
    if (null >= 0) ::close(null);
  }
  ~QuietStderr() {
    if (saved_ < 0) return;
    ::dup2(saved_, STDERR_FILENO);
    ::close(saved_);
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  int saved_;
};

}  // namespace

void OccupancyMap::saveBinary(const std::string& path) {
  tree_->updateInnerOccupancy();
  // The binary format holds occupancy bits only, the same for every tree type, so
  // octomap::OcTree::readBinary and octovis read it. writeBinaryConst leaves our probabilities
  // alone (writeBinary would first threshold the live tree to maximum likelihood).
  writeFileAtomically(path, [&](std::ostream& out) {
    const QuietStderr quiet;
    if (!tree_->writeBinaryConst(out)) throw fileError(path, "OctoMap could not write the tree");
  });
}

void OccupancyMap::saveColor(const std::string& path) {
  tree_->updateInnerOccupancy();
  writeFileAtomically(path, [&](std::ostream& out) {
    if (!tree_->write(out)) throw fileError(path, "OctoMap could not write the tree");
  });
}

}  // namespace pf2
