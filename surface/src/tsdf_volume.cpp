#include "pf2/surface/tsdf_volume.h"

#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include "parallel.h"
#include "pf2/core/error.h"
#include "pf2/surface/marching_cubes.h"

namespace pf2 {

namespace {

constexpr int kSide = TsdfVolume::kBlockSide;

int floorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

void checkImages(const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& K) {
  if (depth.type() != CV_32FC1) throw Error("TsdfVolume: depth must be CV_32F metres");
  if (depth.cols != K.width || depth.rows != K.height) {
    throw Error("TsdfVolume: depth is " + std::to_string(depth.cols) + "x" + std::to_string(depth.rows) +
                " but the intrinsics say " + std::to_string(K.width) + "x" + std::to_string(K.height));
  }
  if (!bgr.empty() && (bgr.type() != CV_8UC3 || bgr.size() != depth.size())) {
    throw Error("TsdfVolume: colour must be CV_8UC3 of the depth's size");
  }
}

// Welding key of the vertex on the edge from global voxel v along `axis` (20 bits per axis).
std::uint64_t edgeKey(const Eigen::Vector3i& v, int axis) {
  const auto field = [](int x) { return static_cast<std::uint64_t>(x + (1 << 19)) & 0xFFFFFu; };
  return (field(v.x()) << 42) | (field(v.y()) << 22) | (field(v.z()) << 2) | static_cast<std::uint64_t>(axis);
}

}  // namespace

TsdfVolume::TsdfVolume(const Options& options) : options_(options) {
  if (!(options_.voxel_size > 0) || !(options_.truncation > 0)) {
    throw Error("TsdfVolume: voxel_size and truncation must be positive");
  }
  options_.allocation_stride = std::max(1, options_.allocation_stride);
}

void TsdfVolume::integrate(const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& K,
                           const Eigen::Isometry3d& T_w_c) {
  update(depth, bgr, K, T_w_c, 1.f);
}

void TsdfVolume::deintegrate(const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& K,
                             const Eigen::Isometry3d& T_w_c) {
  update(depth, bgr, K, T_w_c, -1.f);
}

void TsdfVolume::update(const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& K,
                        const Eigen::Isometry3d& T_w_c, float sign) {
  checkImages(depth, bgr, K);
  const float voxel = static_cast<float>(options_.voxel_size);
  const float truncation = static_cast<float>(options_.truncation);
  const float min_depth = static_cast<float>(options_.min_depth);
  const float max_depth = static_cast<float>(options_.max_depth);
  const float fx = static_cast<float>(K.fx), fy = static_cast<float>(K.fy);
  const float cx = static_cast<float>(K.cx), cy = static_cast<float>(K.cy);
  const Eigen::Isometry3f T_w_c_f = T_w_c.cast<float>();

  // 1. Blocks along the truncation band of every (stride-th) pixel's ray.
  std::unordered_set<Eigen::Vector3i, IndexHash> touched;
  const float inverse_voxel = 1.f / voxel;
  const int stride = options_.allocation_stride;
  for (int v = 0; v < depth.rows; v += stride) {
    const float* row = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; u += stride) {
      const float d = row[u];
      if (!(d >= min_depth && d <= max_depth)) continue;
      const Eigen::Vector3f ray_c((u - cx) / fx, (v - cy) / fy, 1.f);
      const Eigen::Vector3f p0_w = T_w_c_f * (ray_c * (d - truncation));
      const Eigen::Vector3f p1_w = T_w_c_f * (ray_c * (d + truncation));
      const int samples = static_cast<int>(std::ceil((p1_w - p0_w).norm() * inverse_voxel)) + 1;
      Eigen::Vector3i last(INT32_MIN, 0, 0);
      for (int s = 0; s <= samples; ++s) {
        const Eigen::Vector3f p_w = p0_w + (p1_w - p0_w) * (static_cast<float>(s) / samples);
        const Eigen::Vector3i block((p_w * inverse_voxel).array().round().cast<int>().unaryExpr(
            [](int x) { return floorDiv(x, kSide); }));
        if (block == last) continue;
        last = block;
        touched.insert(block);
      }
    }
  }
  std::vector<std::pair<Eigen::Vector3i, Block*>> work;
  work.reserve(touched.size());
  for (const auto& index : touched) {
    auto it = blocks_.find(index);
    if (it == blocks_.end()) {
      if (sign < 0) continue;  // de-integration never allocates: nothing of this frame is there
      it = blocks_.emplace(index, std::make_unique<Block>()).first;
    }
    work.emplace_back(index, it->second.get());
  }

  // 2. Per block, project every voxel into the image and average the observation in.
  const Eigen::Matrix3f R_c_w = T_w_c_f.linear().transpose();
  const Eigen::Vector3f t_c_w = -R_c_w * T_w_c_f.translation();
  const Eigen::Vector3f step_x = R_c_w.col(0) * voxel, step_y = R_c_w.col(1) * voxel,
                        step_z = R_c_w.col(2) * voxel;
  const float u_max = depth.cols - 0.5f, v_max = depth.rows - 0.5f;
  const bool colour = !bgr.empty();
  std::vector<char> emptied(work.size(), 0);
  surface_detail::parallelChunks(work.size(), options_.num_threads, 16, [&](int, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      Block& block = *work[i].second;
      const Eigen::Vector3f origin_w = (work[i].first * kSide).cast<float>() * voxel;
      const Eigen::Vector3f origin_c = R_c_w * origin_w + t_c_w;
      bool any_weight = false;
      for (int z = 0; z < kSide; ++z) {
        for (int y = 0; y < kSide; ++y) {
          Eigen::Vector3f p_c = origin_c + step_y * static_cast<float>(y) + step_z * static_cast<float>(z);
          Voxel* voxel_row = &block.voxels[kSide * (y + kSide * z)];
          for (int x = 0; x < kSide; ++x, p_c += step_x) {
            Voxel& vox = voxel_row[x];
            if (p_c.z() < min_depth) continue;
            const float inverse_z = 1.f / p_c.z();
            const float fu = fx * p_c.x() * inverse_z + cx, fv = fy * p_c.y() * inverse_z + cy;
            if (!(fu >= -0.5f && fu < u_max && fv >= -0.5f && fv < v_max)) continue;
            const int u = static_cast<int>(fu + 0.5f), v = static_cast<int>(fv + 0.5f);
            const float d = depth.ptr<float>(v)[u];
            if (!(d >= min_depth && d <= max_depth)) continue;
            const float sdf = d - p_c.z();
            if (sdf < -truncation) continue;
            const float observation = std::min(1.f, sdf / truncation);
            const float weight = vox.weight + sign;
            if (weight < 0.5f) {
              vox = Voxel();
              continue;
            }
            vox.tsdf = (vox.tsdf * vox.weight + sign * observation) / weight;
            if (colour) {
              const cv::Vec3b& c = bgr.ptr<cv::Vec3b>(v)[u];
              vox.r = (vox.r * vox.weight + sign * c[2]) / weight;
              vox.g = (vox.g * vox.weight + sign * c[1]) / weight;
              vox.b = (vox.b * vox.weight + sign * c[0]) / weight;
            }
            vox.weight = weight;
          }
        }
      }
      // Every kept block holds weight: blocks this frame allocated but never reached, and blocks
      // de-integration emptied, go (so integrate + deintegrate leaves the block set as it was).
      for (const Voxel& vox : block.voxels) any_weight = any_weight || vox.weight > 0.f;
      emptied[i] = !any_weight;
    }
  });
  for (std::size_t i = 0; i < work.size(); ++i) {
    if (emptied[i]) blocks_.erase(work[i].first);
  }
}

const TsdfVolume::Voxel* TsdfVolume::voxel(const Eigen::Vector3d& p_w) const {
  const Eigen::Vector3i v = (p_w / options_.voxel_size).array().round().cast<int>();
  const Eigen::Vector3i block(floorDiv(v.x(), kSide), floorDiv(v.y(), kSide), floorDiv(v.z(), kSide));
  const auto it = blocks_.find(block);
  if (it == blocks_.end()) return nullptr;
  const Eigen::Vector3i local = v - block * kSide;
  return &it->second->voxels[local.x() + kSide * (local.y() + kSide * local.z())];
}

std::size_t TsdfVolume::memoryBytes() const {
  // Node: key, pointer, cached hash and the next pointer (libstdc++), plus the bucket array.
  const std::size_t node = sizeof(Eigen::Vector3i) + 3 * sizeof(void*);
  return blocks_.size() * (sizeof(Block) + node) + blocks_.bucket_count() * sizeof(void*);
}

std::size_t TsdfVolume::removeBlocksFartherThan(const Eigen::Vector3d& p_w, double distance) {
  const double block_size = options_.voxel_size * kSide;
  const Eigen::Vector3d centre_offset = Eigen::Vector3d::Constant(0.5 * (kSide - 1) * options_.voxel_size);
  std::size_t removed = 0;
  for (auto it = blocks_.begin(); it != blocks_.end();) {
    const Eigen::Vector3d centre_w = it->first.cast<double>() * block_size + centre_offset;
    if ((centre_w - p_w).norm() > distance) {
      it = blocks_.erase(it);
      ++removed;
    } else {
      ++it;
    }
  }
  return removed;
}

TriangleMesh TsdfVolume::extractMesh() const {
  struct EdgeVertex {
    std::uint64_t key;
    Eigen::Vector3f p_w;
    std::array<std::uint8_t, 3> rgb;
  };
  struct Part {
    std::vector<EdgeVertex> vertices;
    std::vector<std::array<std::uint64_t, 3>> triangles;
  };
  std::vector<std::pair<Eigen::Vector3i, const Block*>> all;
  all.reserve(blocks_.size());
  for (const auto& entry : blocks_) all.emplace_back(entry.first, entry.second.get());
  // One part per chunk of blocks, merged in chunk order: the mesh is the same whatever the threads.
  constexpr std::size_t kChunk = 32;
  std::vector<Part> parts((all.size() + kChunk - 1) / kChunk);
  const float voxel = static_cast<float>(options_.voxel_size);
  const float min_weight = std::max(options_.mesh_min_weight, 1e-6f);

  surface_detail::parallelChunks(all.size(), options_.num_threads, kChunk, [&](int, std::size_t begin, std::size_t end) {
    Part& part = parts[begin / kChunk];
    for (std::size_t i = begin; i < end; ++i) {
      const Eigen::Vector3i& index = all[i].first;
      // The block and its seven neighbours on the positive side, by offset bits x | y << 1 | z << 2.
      std::array<const Block*, 8> near{};
      for (int n = 0; n < 8; ++n) {
        if (n == 0) {
          near[0] = all[i].second;
          continue;
        }
        const auto it = blocks_.find(index + Eigen::Vector3i(n & 1, (n >> 1) & 1, (n >> 2) & 1));
        near[n] = it == blocks_.end() ? nullptr : it->second.get();
      }
      const auto at = [&near](int x, int y, int z) -> const Voxel* {
        const int n = (x >= kSide ? 1 : 0) | (y >= kSide ? 2 : 0) | (z >= kSide ? 4 : 0);
        if (!near[n]) return nullptr;
        return &near[n]->voxels[(x % kSide) + kSide * ((y % kSide) + kSide * (z % kSide))];
      };
      for (int z = 0; z < kSide; ++z) {
        for (int y = 0; y < kSide; ++y) {
          for (int x = 0; x < kSide; ++x) {
            std::array<const Voxel*, 8> corner;
            int cube_case = 0;
            bool valid = true;
            for (int c = 0; c < 8 && valid; ++c) {
              corner[c] = at(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1));
              valid = corner[c] && corner[c]->weight >= min_weight;
              if (valid && corner[c]->tsdf < 0.f) cube_case |= 1 << c;
            }
            if (!valid || cube_case == 0 || cube_case == 255) continue;
            const auto& cube_triangles = marching_cubes::triangles(cube_case);
            // A jump of more than half the range between neighbours is two truncated sides (a thin
            // object seen from both sides, or the back of the band), not a surface.
            bool consistent = true;
            for (int e = 0; e < 12 && consistent; ++e) {
              const Voxel* a = corner[marching_cubes::kEdgeCorners[e][0]];
              const Voxel* b = corner[marching_cubes::kEdgeCorners[e][1]];
              if ((a->tsdf < 0.f) != (b->tsdf < 0.f)) consistent = std::abs(a->tsdf - b->tsdf) <= 1.f;
            }
            if (!consistent) continue;
            const Eigen::Vector3i base = index * kSide + Eigen::Vector3i(x, y, z);
            std::array<std::uint64_t, 12> keys{};
            std::array<bool, 12> made{};
            for (const auto& triangle : cube_triangles) {
              std::array<std::uint64_t, 3> t;
              for (int k = 0; k < 3; ++k) {
                const int e = triangle[k];
                if (!made[e]) {
                  const int c0 = marching_cubes::kEdgeCorners[e][0], c1 = marching_cubes::kEdgeCorners[e][1];
                  const Voxel& a = *corner[c0];
                  const Voxel& b = *corner[c1];
                  const float s = a.tsdf / (a.tsdf - b.tsdf);
                  const Eigen::Vector3i lower = base + Eigen::Vector3i(c0 & 1, (c0 >> 1) & 1, (c0 >> 2) & 1);
                  Eigen::Vector3f p_w = lower.cast<float>() * voxel;
                  p_w[marching_cubes::kEdgeAxis[e]] += s * voxel;
                  const auto mix = [s](float p, float q) {
                    return static_cast<std::uint8_t>(std::lround(std::clamp(p + s * (q - p), 0.f, 255.f)));
                  };
                  keys[e] = edgeKey(lower, marching_cubes::kEdgeAxis[e]);
                  made[e] = true;
                  part.vertices.push_back({keys[e], p_w, {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)}});
                }
                t[k] = keys[e];
              }
              part.triangles.push_back(t);
            }
          }
        }
      }
    }
  });

  TriangleMesh mesh;
  std::unordered_map<std::uint64_t, int> index_of;
  for (const Part& part : parts) {
    for (const EdgeVertex& vertex : part.vertices) {
      if (index_of.emplace(vertex.key, static_cast<int>(mesh.vertices.size())).second) {
        mesh.vertices.push_back(vertex.p_w);
        mesh.colors.push_back(vertex.rgb);
      }
    }
  }
  for (const Part& part : parts) {
    for (const auto& t : part.triangles) {
      mesh.triangles.emplace_back(index_of.at(t[0]), index_of.at(t[1]), index_of.at(t[2]));
    }
  }
  return mesh;
}

}  // namespace pf2
