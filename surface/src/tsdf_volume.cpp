#include "pf2/surface/tsdf_volume.h"

#include <cmath>
#include <limits>
#include <unordered_map>
#include <algorithm>

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

// Block coordinates packed 21 bits each (+-1M blocks: +-80 km at 1 cm voxels).
std::uint64_t blockKey(const Eigen::Vector3i& b) {
  const auto field = [](int x) { return static_cast<std::uint64_t>(x + (1 << 20)) & 0x1FFFFFu; };
  return (field(b.x()) << 42) | (field(b.y()) << 21) | field(b.z());
}
Eigen::Vector3i blockFromKey(std::uint64_t key) {
  const auto field = [](std::uint64_t bits) { return static_cast<int>(bits & 0x1FFFFFu) - (1 << 20); };
  return Eigen::Vector3i(field(key >> 42), field(key >> 21), field(key));
}

// update()'s frame constants as floats, shared by the block allocation and the voxel update.
struct FrameGeometry {
  float voxel, truncation, min_depth, max_depth;
  float fx, fy, cx, cy;
  Eigen::Isometry3f T_w_c;
};

// Reads the options, intrinsics and pose into floats once per frame (the whole update is float).
FrameGeometry frameGeometry(const TsdfVolume::Options& options, const CameraIntrinsics& K,
                            const Eigen::Isometry3d& T_w_c) {
  FrameGeometry g;
  g.voxel = static_cast<float>(options.voxel_size);
  g.truncation = static_cast<float>(options.truncation);
  g.min_depth = static_cast<float>(options.min_depth);
  g.max_depth = static_cast<float>(options.max_depth);
  g.fx = static_cast<float>(K.fx), g.fy = static_cast<float>(K.fy);
  g.cx = static_cast<float>(K.cx), g.cy = static_cast<float>(K.cy);
  g.T_w_c = T_w_c.cast<float>();
  return g;
}

// Appends the blocks segment g0 -> g1 crosses (block b spans [b, b + 1)), by Amanatides & Woo's grid walk.
void walkBlocks(const Eigen::Vector3f& g0, const Eigen::Vector3f& g1, std::vector<std::uint64_t>& recent,
                std::vector<std::uint64_t>& keys) {
  const Eigen::Vector3f direction = g1 - g0;
  Eigen::Vector3i cell(static_cast<int>(std::floor(g0.x())), static_cast<int>(std::floor(g0.y())),
                       static_cast<int>(std::floor(g0.z())));
  const Eigen::Vector3i last(static_cast<int>(std::floor(g1.x())), static_cast<int>(std::floor(g1.y())),
                             static_cast<int>(std::floor(g1.z())));
  Eigen::Vector3i step;
  Eigen::Vector3f t_max, t_delta;
  for (int a = 0; a < 3; ++a) {
    step[a] = direction[a] > 0 ? 1 : -1;
    const float magnitude = std::abs(direction[a]);
    t_delta[a] = magnitude > 0 ? 1.f / magnitude : std::numeric_limits<float>::infinity();
    const float boundary = static_cast<float>(cell[a] + (step[a] > 0 ? 1 : 0));
    t_max[a] = magnitude > 0 ? (boundary - g0[a]) / direction[a] : std::numeric_limits<float>::infinity();
  }
  const int max_steps = (last - cell).cwiseAbs().sum();
  for (int n = 0;; ++n) {
    const std::uint64_t key = blockKey(cell);
    // A small direct-mapped filter drops the repeats of neighbouring rays before sorting.
    std::uint64_t& seen = recent[(key * 0x9E3779B97F4A7C15ull) >> 56];
    if (seen != key) {
      seen = key;
      keys.push_back(key);
    }
    if (n >= max_steps) break;
    int axis = 0;
    if (t_max[1] < t_max[axis]) axis = 1;
    if (t_max[2] < t_max[axis]) axis = 2;
    cell[axis] += step[axis];
    t_max[axis] += t_delta[axis];
  }
}

// Sorted unique packed keys of the blocks on every stride-th pixel ray's truncation band (to allocate them).
std::vector<std::uint64_t> bandBlockKeys(const cv::Mat& depth, const FrameGeometry& g, int stride, int num_threads) {
  const float inverse_voxel = 1.f / g.voxel;
  constexpr float kInverseSide = 1.f / kSide;
  const float half_voxel = 0.5f * kInverseSide;
  const int rows = (depth.rows + stride - 1) / stride;
  std::vector<std::vector<std::uint64_t>> candidates(std::max(1, num_threads));
  surface_detail::parallelChunks(rows, num_threads, 8, [&](int worker, std::size_t begin, std::size_t end) {
    std::vector<std::uint64_t>& keys = candidates[worker];
    std::vector<std::uint64_t> recent(256, ~std::uint64_t{0});
    for (std::size_t row = begin; row < end; ++row) {
      const int v = static_cast<int>(row) * stride;
      const float* depth_row = depth.ptr<float>(v);
      for (int u = 0; u < depth.cols; u += stride) {
        const float d = depth_row[u];
        if (!(d >= g.min_depth && d <= g.max_depth)) continue;
        const Eigen::Vector3f ray_c((u - g.cx) / g.fx, (v - g.cy) / g.fy, 1.f);
        // The band's segment in block units.
        const Eigen::Vector3f g0 = (g.T_w_c * (ray_c * (d - g.truncation)) * inverse_voxel).array() * kInverseSide + half_voxel;
        const Eigen::Vector3f g1 = (g.T_w_c * (ray_c * (d + g.truncation)) * inverse_voxel).array() * kInverseSide + half_voxel;
        walkBlocks(g0, g1, recent, keys);
      }
    }
  });
  // A sorted vector is much cheaper than a hash set for the few hundred thousand candidates of a frame.
  std::vector<std::uint64_t> touched;
  for (const auto& keys : candidates) touched.insert(touched.end(), keys.begin(), keys.end());
  std::sort(touched.begin(), touched.end());
  touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
  return touched;
}

using BlockWork = std::vector<std::pair<Eigen::Vector3i, TsdfVolume::Block*>>;

// The blocks of `touched`, allocated when integrating; de-integration (sign < 0) skips missing ones.
BlockWork workBlocks(const std::vector<std::uint64_t>& touched, float sign, TsdfVolume::BlockMap& blocks) {
  BlockWork work;
  work.reserve(touched.size());
  for (const std::uint64_t key : touched) {
    const Eigen::Vector3i index = blockFromKey(key);
    auto it = blocks.find(index);
    if (it == blocks.end()) {
      if (sign < 0) continue;  // de-integration never allocates: nothing of this frame is there
      it = blocks.emplace(index, std::make_unique<TsdfVolume::Block>()).first;
    }
    work.emplace_back(index, it->second.get());
  }
  return work;
}

// Voxel centres to this frame's pixels: q = K (R_c_w p_w + t_c_w) homogeneous, stepped per voxel, and the images.
struct VoxelProjection {
  Eigen::Matrix3f P;
  Eigen::Vector3f Kt, step_x, step_y, step_z;
  float voxel, truncation, inverse_truncation, min_depth, max_depth, u_max, v_max, sign;
  bool colour;
  const float* depth_data;
  std::size_t depth_step;
  const unsigned char* bgr_data;
  std::size_t bgr_step;
};

// Builds the projection of world voxels into this frame's depth and colour images.
VoxelProjection voxelProjection(const cv::Mat& depth, const cv::Mat& bgr, const FrameGeometry& g, float sign) {
  VoxelProjection p;
  const Eigen::Matrix3f R_c_w = g.T_w_c.linear().transpose();
  const Eigen::Vector3f t_c_w = -R_c_w * g.T_w_c.translation();
  Eigen::Matrix3f K_f;
  K_f << g.fx, 0.f, g.cx, 0.f, g.fy, g.cy, 0.f, 0.f, 1.f;
  p.P = K_f * R_c_w;
  p.Kt = K_f * t_c_w;
  p.step_x = p.P.col(0) * g.voxel, p.step_y = p.P.col(1) * g.voxel, p.step_z = p.P.col(2) * g.voxel;
  p.voxel = g.voxel, p.truncation = g.truncation, p.min_depth = g.min_depth, p.max_depth = g.max_depth;
  p.u_max = depth.cols - 0.5f, p.v_max = depth.rows - 0.5f;
  p.sign = sign;
  p.colour = !bgr.empty();
  p.inverse_truncation = 1.f / g.truncation;
  p.depth_data = depth.ptr<float>(0);
  p.depth_step = depth.step1();
  p.bgr_data = p.colour ? bgr.ptr<unsigned char>(0) : nullptr;
  p.bgr_step = p.colour ? bgr.step1() : 0;
  return p;
}

// Averages this frame's observations into (sign -1: out of) one block's voxels; false when no weight is left.
bool updateBlock(const VoxelProjection& projection, const Eigen::Vector3i& index, TsdfVolume::Block& block) {
  using Voxel = TsdfVolume::Voxel;
  // A local copy: the compiler keeps it in registers instead of reloading it after voxel stores.
  const VoxelProjection c = projection;
  const Eigen::Vector3f origin_w = (index * kSide).cast<float>() * c.voxel;
  const Eigen::Vector3f origin_q = c.P * origin_w + c.Kt;
  bool any_weight = false;
  for (int z = 0; z < kSide; ++z) {
    for (int y = 0; y < kSide; ++y) {
      const Eigen::Vector3f row_q = origin_q + c.step_y * static_cast<float>(y) + c.step_z * static_cast<float>(z);
      float qx = row_q.x(), qy = row_q.y(), qz = row_q.z();
      Voxel* voxel_row = &block.voxels[kSide * (y + kSide * z)];
      for (int x = 0; x < kSide; ++x, qx += c.step_x.x(), qy += c.step_x.y(), qz += c.step_x.z()) {
        if (qz < c.min_depth) continue;
        const float inverse_z = 1.f / qz;
        const float fu = qx * inverse_z, fv = qy * inverse_z;
        if (!(fu >= -0.5f && fu < c.u_max && fv >= -0.5f && fv < c.v_max)) continue;
        const int u = static_cast<int>(fu + 0.5f), v = static_cast<int>(fv + 0.5f);
        const float d = c.depth_data[v * c.depth_step + u];
        if (!(d >= c.min_depth && d <= c.max_depth)) continue;
        const float sdf = d - qz;
        if (sdf < -c.truncation) continue;
        Voxel& vox = voxel_row[x];
        const float observation = std::min(1.f, sdf * c.inverse_truncation);
        const float weight = vox.weight + c.sign;
        if (weight < 0.5f) {
          vox = Voxel();
          continue;
        }
        const float inverse_weight = 1.f / weight;
        vox.tsdf = (vox.tsdf * vox.weight + c.sign * observation) * inverse_weight;
        if (c.colour) {
          const unsigned char* rgb = c.bgr_data + v * c.bgr_step + 3 * u;
          vox.r = (vox.r * vox.weight + c.sign * rgb[2]) * inverse_weight;
          vox.g = (vox.g * vox.weight + c.sign * rgb[1]) * inverse_weight;
          vox.b = (vox.b * vox.weight + c.sign * rgb[0]) * inverse_weight;
        }
        vox.weight = weight;
      }
    }
  }
  for (const Voxel& vox : block.voxels) any_weight = any_weight || vox.weight > 0.f;
  return any_weight;
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

// Fuses (sign +1) or removes (sign -1) a frame: band blocks allocated, their voxels averaged, emptied blocks freed.
void TsdfVolume::update(const cv::Mat& depth, const cv::Mat& bgr, const CameraIntrinsics& K,
                        const Eigen::Isometry3d& T_w_c, float sign) {
  checkImages(depth, bgr, K);
  const FrameGeometry geometry = frameGeometry(options_, K, T_w_c);

  // 1. Blocks along the truncation band of every (stride-th) pixel's ray.
  const std::vector<std::uint64_t> touched =
      bandBlockKeys(depth, geometry, options_.allocation_stride, options_.num_threads);
  const BlockWork work = workBlocks(touched, sign, blocks_);

  // 2. Per block, project every voxel into the image and average the observation in.
  const VoxelProjection projection = voxelProjection(depth, bgr, geometry, sign);
  std::vector<char> emptied(work.size(), 0);
  surface_detail::parallelChunks(work.size(), options_.num_threads, 16, [&](int, std::size_t begin, std::size_t end) {
    // Every kept block holds weight: blocks this frame allocated but never reached, and blocks
    // de-integration emptied, go (so integrate + deintegrate leaves the block set as it was).
    for (std::size_t i = begin; i < end; ++i) emptied[i] = !updateBlock(projection, work[i].first, *work[i].second);
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

namespace {

// Marching-cubes output of a chunk of blocks: vertices keyed by the voxel edge they lie on (shared
// between neighbouring cubes and chunks) and triangles of those keys.
struct MeshPart {
  struct EdgeVertex {
    std::uint64_t key;
    Eigen::Vector3f p_w;
    std::array<std::uint8_t, 3> rgb;
  };
  std::vector<EdgeVertex> vertices;
  std::vector<std::array<std::uint64_t, 3>> triangles;
};

using CubeCorners = std::array<const TsdfVolume::Voxel*, 8>;

// A jump of more than half the range between neighbours is two truncated sides (a thin object
// seen from both sides, or the back of the band), not a surface.
bool consistentCube(const CubeCorners& corner) {
  for (int e = 0; e < 12; ++e) {
    const TsdfVolume::Voxel* a = corner[marching_cubes::kEdgeCorners[e][0]];
    const TsdfVolume::Voxel* b = corner[marching_cubes::kEdgeCorners[e][1]];
    if ((a->tsdf < 0.f) != (b->tsdf < 0.f) && std::abs(a->tsdf - b->tsdf) > 1.f) return false;
  }
  return true;
}

// The triangles of one cube (lower corner voxel `base`, case `cube_case`), their vertices
// interpolated on the crossed edges in position and colour.
void polygoniseCube(const CubeCorners& corner, int cube_case, const Eigen::Vector3i& base, float voxel,
                    MeshPart* part) {
  std::array<std::uint64_t, 12> keys{};
  std::array<bool, 12> made{};
  for (const auto& triangle : marching_cubes::triangles(cube_case)) {
    std::array<std::uint64_t, 3> t;
    for (int k = 0; k < 3; ++k) {
      const int e = triangle[k];
      if (!made[e]) {
        const int c0 = marching_cubes::kEdgeCorners[e][0], c1 = marching_cubes::kEdgeCorners[e][1];
        const TsdfVolume::Voxel& a = *corner[c0];
        const TsdfVolume::Voxel& b = *corner[c1];
        const float s = a.tsdf / (a.tsdf - b.tsdf);
        const Eigen::Vector3i lower = base + Eigen::Vector3i(c0 & 1, (c0 >> 1) & 1, (c0 >> 2) & 1);
        Eigen::Vector3f p_w = lower.cast<float>() * voxel;
        p_w[marching_cubes::kEdgeAxis[e]] += s * voxel;
        const auto mix = [s](float p, float q) {
          return static_cast<std::uint8_t>(std::lround(std::clamp(p + s * (q - p), 0.f, 255.f)));
        };
        keys[e] = edgeKey(lower, marching_cubes::kEdgeAxis[e]);
        made[e] = true;
        part->vertices.push_back({keys[e], p_w, {mix(a.r, b.r), mix(a.g, b.g), mix(a.b, b.b)}});
      }
      t[k] = keys[e];
    }
    part->triangles.push_back(t);
  }
}

// Parts merged in order: each edge's vertex once, at its first appearance.
TriangleMesh mergeParts(const std::vector<MeshPart>& parts) {
  TriangleMesh mesh;
  std::unordered_map<std::uint64_t, int> index_of;
  for (const MeshPart& part : parts) {
    for (const MeshPart::EdgeVertex& vertex : part.vertices) {
      if (index_of.emplace(vertex.key, static_cast<int>(mesh.vertices.size())).second) {
        mesh.vertices.push_back(vertex.p_w);
        mesh.colors.push_back(vertex.rgb);
      }
    }
  }
  for (const MeshPart& part : parts) {
    for (const auto& t : part.triangles) {
      mesh.triangles.emplace_back(index_of.at(t[0]), index_of.at(t[1]), index_of.at(t[2]));
    }
  }
  return mesh;
}

}  // namespace

TriangleMesh TsdfVolume::extractMesh() const {
  std::vector<std::pair<Eigen::Vector3i, const Block*>> all;
  all.reserve(blocks_.size());
  for (const auto& entry : blocks_) all.emplace_back(entry.first, entry.second.get());
  // One part per chunk of blocks, merged in chunk order: the mesh is the same whatever the threads.
  constexpr std::size_t kChunk = 32;
  std::vector<MeshPart> parts((all.size() + kChunk - 1) / kChunk);
  const float voxel = static_cast<float>(options_.voxel_size);
  const float min_weight = std::max(options_.mesh_min_weight, 1e-6f);

  surface_detail::parallelChunks(all.size(), options_.num_threads, kChunk, [&](int, std::size_t begin, std::size_t end) {
    MeshPart& part = parts[begin / kChunk];
    for (std::size_t i = begin; i < end; ++i) {
      const Eigen::Vector3i& index = all[i].first;
      // The block and its seven neighbours on the positive side, by offset bits x | y << 1 | z << 2.
      std::array<const Block*, 8> near{};
      near[0] = all[i].second;
      for (int n = 1; n < 8; ++n) {
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
            CubeCorners corner;
            int cube_case = 0;
            bool valid = true;
            for (int c = 0; c < 8 && valid; ++c) {
              corner[c] = at(x + (c & 1), y + ((c >> 1) & 1), z + ((c >> 2) & 1));
              valid = corner[c] && corner[c]->weight >= min_weight;
              if (valid && corner[c]->tsdf < 0.f) cube_case |= 1 << c;
            }
            if (!valid || cube_case == 0 || cube_case == 255 || !consistentCube(corner)) continue;
            polygoniseCube(corner, cube_case, index * kSide + Eigen::Vector3i(x, y, z), voxel, &part);
          }
        }
      }
    }
  });
  return mergeParts(parts);
}

}  // namespace pf2
