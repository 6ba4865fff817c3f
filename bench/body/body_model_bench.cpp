// evaluate() of the shipped default model: the synthetic generator calls it per person per frame
// at 30 Hz, the fitter many times per frame, so it must stay well under 2 ms.
#include <benchmark/benchmark.h>

#include "pf2/body/body_model.h"

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
