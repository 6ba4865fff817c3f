// Speed of the mapping engine at 640x480 and 1 cm voxels on an analytic box room (4 x 2.7 x 4 m,
// the camera near its middle, walls 1.7-2.3 m away).
#include <limits>

#include <benchmark/benchmark.h>

#include "analytic_scene.h"
#include "pf2/surface/mapper.h"
#include "pf2/surface/occupancy_map.h"
#include "pf2/surface/tsdf_volume.h"
#include "pf2/surface/up_direction.h"

namespace pf2 {
namespace {

struct RoomFrames {
  CameraIntrinsics K;
  std::vector<Eigen::Isometry3d> poses;
  std::vector<cv::Mat> depths, colours;
  RoomFrames() {
    test::AnalyticScene scene = test::boxRoom();
    scene.spheres.push_back({Eigen::Vector3d(0.8, 0.6, 1.2), 0.4});
    scene.boxes.push_back({Eigen::Vector3d(-1.2, 0.4, 0.6), Eigen::Vector3d(-0.4, 1.2, 1.4)});
    for (int i = 0; i < 16; ++i) {
      const double angle = i * M_PI / 8;
      const Eigen::Vector3d p_w(0.3 * std::cos(angle), -0.2, 0.3 * std::sin(angle));
      poses.push_back(test::lookAt(p_w, p_w + Eigen::Vector3d(std::cos(angle), 0.25, std::sin(angle))));
      cv::Mat depth, bgr;
      scene.render(K, poses.back(), &depth, &bgr);
      depths.push_back(depth);
      colours.push_back(bgr);
    }
  }
  static const RoomFrames& get() {
    static const RoomFrames frames;
    return frames;
  }
};

TsdfVolume::Options tsdfOptions(const benchmark::State& state) {
  TsdfVolume::Options options;
  options.num_threads = static_cast<int>(state.range(0));
  return options;
}

// Steady state: every view fused once before timing, so blocks exist as in a running SLAM.
void BM_TsdfIntegrate(benchmark::State& state) {
  const RoomFrames& f = RoomFrames::get();
  TsdfVolume volume(tsdfOptions(state));
  for (size_t i = 0; i < f.poses.size(); ++i) volume.integrate(f.depths[i], f.colours[i], f.K, f.poses[i]);
  size_t i = 0;
  for (auto _ : state) {
    volume.integrate(f.depths[i], f.colours[i], f.K, f.poses[i]);
    i = (i + 1) % f.poses.size();
  }
  state.counters["blocks"] = static_cast<double>(volume.blockCount());
}
BENCHMARK(BM_TsdfIntegrate)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

// A fresh volume per frame: allocation of every touched block included.
void BM_TsdfIntegrateFirstFrame(benchmark::State& state) {
  const RoomFrames& f = RoomFrames::get();
  for (auto _ : state) {
    state.PauseTiming();
    TsdfVolume volume(tsdfOptions(state));
    state.ResumeTiming();
    volume.integrate(f.depths[0], f.colours[0], f.K, f.poses[0]);
    state.PauseTiming();
    volume.clear();
    state.ResumeTiming();
  }
}
BENCHMARK(BM_TsdfIntegrateFirstFrame)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

// One keyframe moved: de-integrate at the old pose, integrate at the new one.
void BM_TsdfReintegrate(benchmark::State& state) {
  const RoomFrames& f = RoomFrames::get();
  TsdfVolume volume(tsdfOptions(state));
  for (size_t i = 0; i < f.poses.size(); ++i) volume.integrate(f.depths[i], f.colours[i], f.K, f.poses[i]);
  Eigen::Isometry3d moved = f.poses[3];
  moved.pretranslate(Eigen::Vector3d(0.01, 0.0, 0.0));
  bool at_moved = false;
  for (auto _ : state) {
    volume.deintegrate(f.depths[3], f.colours[3], f.K, at_moved ? moved : f.poses[3]);
    volume.integrate(f.depths[3], f.colours[3], f.K, at_moved ? f.poses[3] : moved);
    at_moved = !at_moved;
  }
}
BENCHMARK(BM_TsdfReintegrate)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

void BM_ExtractMesh(benchmark::State& state) {
  const RoomFrames& f = RoomFrames::get();
  TsdfVolume volume(tsdfOptions(state));
  for (size_t i = 0; i < f.poses.size(); ++i) volume.integrate(f.depths[i], f.colours[i], f.K, f.poses[i]);
  size_t vertices = 0;
  for (auto _ : state) {
    const TriangleMesh mesh = volume.extractMesh();
    vertices = mesh.vertices.size();
    benchmark::DoNotOptimize(mesh.triangles.data());
  }
  state.counters["blocks"] = static_cast<double>(volume.blockCount());
  state.counters["vertices"] = static_cast<double>(vertices);
}
BENCHMARK(BM_ExtractMesh)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);

// OctoMap insertion of one 640x480 frame (every 4th pixel, 5 cm cells, 4 m rays).
void BM_OccupancyInsert(benchmark::State& state) {
  const RoomFrames& f = RoomFrames::get();
  OccupancyMap::Options options;
  options.pixel_stride = static_cast<int>(state.range(0));
  OccupancyMap map(options);
  size_t i = 0;
  for (auto _ : state) {
    map.insert(f.depths[i], f.colours[i], f.K, f.poses[i]);
    i = (i + 1) % f.poses.size();
  }
}
BENCHMARK(BM_OccupancyInsert)->Arg(4)->Arg(8)->Unit(benchmark::kMillisecond);

// Everything a keyframe costs the Mapper: compression, decoding, TSDF and OctoMap insertion.
void BM_MapperAddKeyframe(benchmark::State& state) {
  const RoomFrames& f = RoomFrames::get();
  Mapper mapper;
  int id = 0;
  for (auto _ : state) {
    const size_t i = id % f.poses.size();
    mapper.addKeyframe(id++, f.depths[i], f.colours[i], f.K, f.poses[i]);
  }
  state.counters["stored_MB"] = static_cast<double>(mapper.memoryBytes()) / 1e6;
}
BENCHMARK(BM_MapperAddKeyframe)->UseRealTime()->Unit(benchmark::kMillisecond)->Iterations(48);

// One frame's look for the world's up (UpDirectionEstimator::update) as long as it has not
// settled: pf2_slam pays this on every frame of a run whose view never shows floor or table tops.
void BM_UpDirectionUpdate(benchmark::State& state) {
  const RoomFrames& f = RoomFrames::get();
  UpDirectionEstimator::Options options;
  options.settled_normals = std::numeric_limits<int>::max();  // never settles: every call works
  UpDirectionEstimator up(options);
  size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(up.update(f.depths[i], f.K, f.poses[i]));
    i = (i + 1) % f.poses.size();
  }
}
BENCHMARK(BM_UpDirectionUpdate)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace pf2

BENCHMARK_MAIN();
