// Google Benchmark micro-benchmarks of the registration stage at 640x480: frame preparation,
// dense refinement, keyframe creation and whole-frame tracking (rendered room; and real TUM
// fr1/rpy frames when ../shared/data is present).
#include <sys/stat.h>

#include <benchmark/benchmark.h>

#include "../../tests/registration/rendered_scene.h"
#include "pf2/io/tum_sequence.h"
#include "pf2/registration/tracker.h"

namespace pf2 {
namespace {

Eigen::Isometry3d pathPose(int i) {
  return test::cameraPose(0.004 * i, -0.1, -0.5 + 0.003 * i, 0.02, 0.004 * i, 0.0);
}

// 30 rendered frames, played forward then backward so the motion stays continuous.
const std::vector<Frame>& renderedPath() {
  static const std::vector<Frame> frames = [] {
    std::vector<Frame> out;
    for (int i = 0; i < 30; ++i)
      out.push_back(test::renderRoom(pathPose(i), CameraIntrinsics::tumFreiburg1(), i));
    for (int i = 28; i > 0; --i) out.push_back(out[i]);
    return out;
  }();
  return frames;
}

void BM_Prepare(benchmark::State& state) {
  RgbdOdometry odometry;
  const Frame& frame = renderedPath()[0];
  for (auto _ : state) benchmark::DoNotOptimize(odometry.prepare(frame));
}
BENCHMARK(BM_Prepare)->Unit(benchmark::kMillisecond);

void BM_MakeReference(benchmark::State& state) {
  RgbdOdometry odometry;
  const OdometryFrame prepared = odometry.prepare(renderedPath()[0]);
  for (auto _ : state) {
    OdometryFrame frame = prepared;
    odometry.makeReference(&frame);
    benchmark::DoNotOptimize(frame.keypoints.size());
  }
}
BENCHMARK(BM_MakeReference)->Unit(benchmark::kMillisecond);

void BM_DenseRefine(benchmark::State& state) {
  RgbdOdometry odometry;
  OdometryFrame reference = odometry.prepare(renderedPath()[0]);
  odometry.makeReference(&reference);
  const OdometryFrame current = odometry.prepare(renderedPath()[3]);
  for (auto _ : state)
    benchmark::DoNotOptimize(odometry.refine(reference, current, Eigen::Isometry3d::Identity()));
}
BENCHMARK(BM_DenseRefine)->Unit(benchmark::kMillisecond);

void trackLoop(benchmark::State& state, const std::vector<Frame>& frames,
               const Tracker::Options& options) {
  Tracker tracker(options);
  size_t i = 0;
  for (auto _ : state) {
    const TrackResult r = tracker.track(frames[i]);
    if (r.status == TrackStatus::kLost) state.SkipWithError("tracking lost");
    i = (i + 1) % frames.size();
  }
  tracker.finish();
}

void BM_TrackRendered(benchmark::State& state) {
  trackLoop(state, renderedPath(), Tracker::Options());
}
BENCHMARK(BM_TrackRendered)->Unit(benchmark::kMillisecond)->Iterations(300);

void BM_TrackTumRpy(benchmark::State& state) {
  const std::string folder = std::string(PF2_SHARED_DATA) + "/tum_fr1_rpy_120";
  struct stat info;
  if (::stat((folder + "/rgb.txt").c_str(), &info) != 0) {
    state.SkipWithError("no ../shared/data/tum_fr1_rpy_120");
    for (auto _ : state) {
    }
    return;
  }
  static const std::vector<Frame> frames = [&] {
    const TumSequence sequence(folder);
    std::vector<Frame> out;
    for (size_t i = 0; i < sequence.size(); ++i) out.push_back(sequence.frame(i));
    for (size_t i = sequence.size() - 2; i > 0; --i) out.push_back(out[i]);
    return out;
  }();
  Tracker::Options options;
  options.odometry.distortion = kTumFreiburg1Distortion;
  trackLoop(state, frames, options);
}
BENCHMARK(BM_TrackTumRpy)->Unit(benchmark::kMillisecond)->Iterations(476);

}  // namespace
}  // namespace pf2

BENCHMARK_MAIN();
