// evaluate() of the shipped default model: the synthetic generator calls it per person per frame
// at 30 Hz, the fitter many times per frame, so it must stay well under 2 ms.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "pf2/body/body_model.h"
#include "pf2/body/npy.h"

namespace {

const pf2::BodyModel& model() {
  static const pf2::BodyModel m = pf2::BodyModel::loadDefault();
  return m;
}

pf2::BodyParameters walkingParameters() {
  pf2::BodyParameters p;
  p.shape = Eigen::VectorXd::LinSpaced(model().shapeCount(), -1.0, 1.0);
  for (int j = 0; j < pf2::kBodyJointCount; ++j) p.pose[j] = Eigen::Vector3d(0.1 * (j % 3), -0.05 * (j % 2), 0.02 * j);
  p.translation = Eigen::Vector3d(0.3, 0.0, 2.5);
  return p;
}

void BM_EvaluateDefaultModel(benchmark::State& state) {
  const pf2::BodyParameters p = walkingParameters();
  for (auto _ : state) {
    pf2::BodyMesh mesh = model().evaluate(p);
    benchmark::DoNotOptimize(mesh.vertices.data());
  }
  state.counters["vertices"] = model().vertexCount();
}
BENCHMARK(BM_EvaluateDefaultModel)->Unit(benchmark::kMicrosecond);

// The same mesh with (random) pose blend shapes, as the official SMPL model has: the cost of the
// extra (3V x 207) product. SMPL has 6 890 vertices, about half of these.
void BM_EvaluateWithPoseBlendShapes(benchmark::State& state) {
  static const pf2::BodyModel with_posedirs = [] {
    const pf2::NpzReader npz(pf2::BodyModel::defaultModelPath());
    std::vector<std::pair<std::string, pf2::NpyArray>> arrays;
    for (const auto& name : npz.names()) arrays.emplace_back(name, npz.read(name));
    for (auto& [name, array] : arrays) {
      if (name != "posedirs") continue;
      std::vector<float> values(array.elementCount());
      std::uint32_t state = 12345;
      for (float& v : values) v = static_cast<float>((state = state * 1664525u + 1013904223u) >> 8) * 1e-10f;
      array = pf2::NpyArray::fromFloats(array.shape, values);
    }
    const std::string path = "/tmp/pf2_body_bench_posedirs.npz";
    pf2::writeNpz(path, arrays);
    pf2::BodyModel model = pf2::BodyModel::loadNpz(path);
    std::remove(path.c_str());
    return model;
  }();
  const pf2::BodyParameters p = walkingParameters();
  for (auto _ : state) {
    pf2::BodyMesh mesh = with_posedirs.evaluate(p);
    benchmark::DoNotOptimize(mesh.vertices.data());
  }
}
BENCHMARK(BM_EvaluateWithPoseBlendShapes)->Unit(benchmark::kMicrosecond);

void BM_RestJoints(benchmark::State& state) {
  const Eigen::VectorXd shape = Eigen::VectorXd::Constant(model().shapeCount(), 0.5);
  for (auto _ : state) benchmark::DoNotOptimize(model().restJoints(shape));
}
BENCHMARK(BM_RestJoints)->Unit(benchmark::kMicrosecond);

void BM_LoadDefaultModel(benchmark::State& state) {
  for (auto _ : state) benchmark::DoNotOptimize(pf2::BodyModel::loadDefault().vertexCount());
}
BENCHMARK(BM_LoadDefaultModel)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
