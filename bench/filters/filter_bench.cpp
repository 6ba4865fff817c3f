// Dual-BBox filter time per 640x480 frame: the paper's filter alone and with each addition.
// The frame: a room (wall at 4 m, floor rising towards the camera) and three people (boxes
// 120x330 px) at 1.5, 2.2 and 3 m, each with a mask; the camera moves 1 cm between frames.
#include <benchmark/benchmark.h>

#include <opencv2/imgproc.hpp>

#include "pf2/core/command_line.h"
#include "pf2/filters/dual_bbox_filter.h"
#include "image_ops.h"

namespace {

struct Scene {
  cv::Mat depth = cv::Mat(480, 640, CV_32F);
  pf2::Detections detections;
  pf2::CameraIntrinsics intrinsics = pf2::CameraIntrinsics::tumFreiburg3();
  Scene() {
    for (int v = 0; v < 480; ++v) {
      for (int u = 0; u < 640; ++u) depth.at<float>(v, u) = v < 300 ? 4.0f : 4.0f - (v - 300) * 0.012f;
    }
    const float distances[3] = {1.5f, 2.2f, 3.0f};
    for (int i = 0; i < 3; ++i) {
      const cv::Rect body(60 + 190 * i, 100, 120, 330);
      pf2::PersonDetection p;
      p.box = pf2::PersonBox{float(body.x), float(body.y), float(body.x + body.width), float(body.y + body.height)};
      p.score = 0.9f;
      p.mask = cv::Mat::zeros(480, 640, CV_8U);
      cv::ellipse(p.mask, cv::Point(body.x + 60, body.y + 165), cv::Size(50, 160), 0, 0, 360, 255, -1);
      depth.setTo(distances[i], p.mask);
      detections.people.push_back(p);
    }
  }
};

void run(benchmark::State& state, bool mask, bool temporal, bool geometric, int depth_gate_radius = 0) {
  const Scene scene;
  pf2::DualBBoxFilter::Options options;
  options.use_mask = mask;
  options.temporal = temporal;
  options.geometric = geometric;
  options.depth_gate.radius = depth_gate_radius;
  pf2::DualBBoxFilter filter(options);
  filter.setIntrinsics(scene.intrinsics);
  auto evidence = std::make_shared<pf2::PredictedDepthEvidence>();
  evidence->setPrediction(cv::Mat(480, 640, CV_32F, cv::Scalar(4.0f)));
  filter.setDynamicEvidence(evidence);
  Eigen::Isometry3d T_cur_prev = Eigen::Isometry3d::Identity();
  T_cur_prev.translation().x() = 0.01;
  filter.filter(scene.depth, scene.detections, T_cur_prev);  // the temporal addition's first frame
  for (auto _ : state) {
    auto result = filter.filter(scene.depth, scene.detections, T_cur_prev);
    benchmark::DoNotOptimize(result.static_depth.data);
  }
}

void BM_DualBBoxPaper(benchmark::State& s) { run(s, false, false, false); }
void BM_DualBBoxMask(benchmark::State& s) { run(s, true, false, false); }
void BM_DualBBoxTemporal(benchmark::State& s) { run(s, false, true, false); }
void BM_DualBBoxGeometric(benchmark::State& s) { run(s, false, false, true); }
void BM_DualBBoxMaskTemporal(benchmark::State& s) { run(s, true, true, false); }  // pf2_slam's default
void BM_DualBBoxAll(benchmark::State& s) { run(s, true, true, true); }
void BM_DualBBoxAllGated(benchmark::State& s) { run(s, true, true, true, 45); }  // + the depth gate at pf2_slam's radius
BENCHMARK(BM_DualBBoxPaper)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DualBBoxMask)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DualBBoxTemporal)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DualBBoxGeometric)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DualBBoxMaskTemporal)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DualBBoxAll)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DualBBoxAllGated)->Unit(benchmark::kMillisecond);

// The 20-pixel disc dilation of a person's mask area (the filter's mask reach): OpenCV's elliptic
// cv::dilate (argument 0) against dilatedByDisc from the kernel's row spans (1, what the filter uses).
void BM_MaskReachDilation(benchmark::State& s) {
  constexpr int kRadius = 20;
  const cv::Mat mask = Scene().detections.people[0].mask(cv::Rect(40, 60, 160, 410)).clone();
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * kRadius + 1, 2 * kRadius + 1));
  cv::Mat out;
  for (auto _ : s) {
    if (s.range(0) == 0) {
      cv::dilate(mask, out, kernel, cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    } else {
      out = pf2::dilatedByDisc(mask, kRadius);
    }
    benchmark::DoNotOptimize(out.data);
  }
}
BENCHMARK(BM_MaskReachDilation)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  pf2::keepFreedImageMemory();  // as the apps do: without it each frame's images page-fault anew
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
