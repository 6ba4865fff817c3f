// Rendering speed of the synthetic sequences: one full frame (people posed and skinned, z-buffer,
// shading, labels, sensor model, ground truth) at 640x480, per people count and option.
#include <ctime>

#include <benchmark/benchmark.h>

#include "pf2/synth/synthetic_sequence.h"

namespace {

// CPU time of the whole process (all threads), seconds: the work per frame, independent of how
// busy the machine is.
double processCpuSeconds() {
  timespec now;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return now.tv_sec + 1e-9 * now.tv_nsec;
}

void renderFrames(benchmark::State& state, pf2::SyntheticSequence::Options options) {
  options.frames = 300;
  const pf2::SyntheticSequence sequence(options);
  size_t i = 0;
  pf2::FrameGroundTruth truth;
  const double cpu_start = processCpuSeconds();
  for (auto _ : state) {
    benchmark::DoNotOptimize(sequence.frame(i, &truth));
    i = (i + 7) % sequence.size();
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["cpu_ms_all_threads"] = 1000.0 * (processCpuSeconds() - cpu_start) / state.iterations();
}

void BM_FramePeople(benchmark::State& state) {
  pf2::SyntheticSequence::Options options;
  options.people = static_cast<int>(state.range(0));
  renderFrames(state, options);
}
BENCHMARK(BM_FramePeople)->Arg(0)->Arg(3)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_FrameBlurLoop(benchmark::State& state) {
  pf2::SyntheticSequence::Options options;
  options.motion_blur = true;
  options.camera = pf2::CameraMotion::kLoop;
  renderFrames(state, options);
}
BENCHMARK(BM_FrameBlurLoop)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SceneBuild(benchmark::State& state) {
  std::uint64_t seed = 100;
  for (auto _ : state) {
    pf2::StaticScene::Options options;
    options.seed = seed++;
    benchmark::DoNotOptimize(pf2::StaticScene(options).mesh().triangles.size());
  }
}
BENCHMARK(BM_SceneBuild)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
