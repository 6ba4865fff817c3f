// Per-frame cost of the human tracking stage: the mean depth of one person's D_h^t (eq. 2) and
// one HumanTracker::update with K people walking in circles.
#include <cmath>

#include <benchmark/benchmark.h>
#include <opencv2/core.hpp>

#include "pf2/humans/human_position.h"
#include "pf2/humans/human_tracker.h"

namespace {

// A person's depth area as the filter gives it: 160 x 360 pixels, two thirds of them the person.
void BM_MeanDepth(benchmark::State& state) {
  cv::Mat depth(360, 160, CV_32F, cv::Scalar(0));
  cv::RNG rng(1);
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) {
      if ((u + v) % 3 != 0) depth.at<float>(v, u) = 2.0f + static_cast<float>(rng.uniform(-0.2, 0.2));
    }
  }
  for (auto _ : state) benchmark::DoNotOptimize(pf2::meanDepth(depth));
}
BENCHMARK(BM_MeanDepth)->Unit(benchmark::kMicrosecond);

// state.range(0): people; state.range(1): 0 paper, 1 predicted. Each update is one 30 Hz frame.
void BM_TrackerUpdate(benchmark::State& state) {
  const int people = static_cast<int>(state.range(0));
  pf2::HumanTracker::Options options;
  options.association = state.range(1) == 0 ? pf2::HumanTracker::Association::kPaper
                                            : pf2::HumanTracker::Association::kPredicted;
  pf2::HumanTracker tracker(options);
  std::vector<Eigen::Vector3d> centres(people);
  int frame = 0;
  for (auto _ : state) {
    const double t = frame++ / 30.0;
    for (int k = 0; k < people; ++k) {
      const double angle = 0.4 * t + 2.0 * M_PI * k / people;
      centres[k] = Eigen::Vector3d(3 + 1.5 * std::cos(angle), 2.5 + 1.5 * std::sin(angle), 1.0);
    }
    benchmark::DoNotOptimize(tracker.update(t, centres));
  }
}
BENCHMARK(BM_TrackerUpdate)->Args({3, 0})->Args({3, 1})->Args({5, 0})->Args({5, 1})->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
