// Detector time per 640x480 frame. HOG's time hardly depends on the content; the frame is a
// textured room with two dark upright figures. (YOLO needs user-supplied weights: measure it
// with pf2_detect --detector yolo, which prints the detector's time per frame.)
#include <benchmark/benchmark.h>

#include <opencv2/imgproc.hpp>

#include "pf2/detection/hog_detector.h"
#include "pf2/detection/box_degradation.h"

namespace {

pf2::Frame frame() {
  pf2::Frame f;
  f.rgb = cv::Mat(480, 640, CV_8UC3);
  cv::randu(f.rgb, cv::Scalar(60, 60, 60), cv::Scalar(200, 200, 200));
  cv::GaussianBlur(f.rgb, f.rgb, cv::Size(7, 7), 2.0);
  for (int i = 0; i < 2; ++i) {
    const int x = 150 + 250 * i;
    cv::ellipse(f.rgb, cv::Point(x, 110), cv::Size(18, 22), 0, 0, 360, cv::Scalar(30, 30, 40), -1);
    cv::rectangle(f.rgb, cv::Rect(x - 35, 132, 70, 130), cv::Scalar(40, 30, 30), -1);
    cv::rectangle(f.rgb, cv::Rect(x - 30, 262, 25, 150), cv::Scalar(30, 30, 30), -1);
    cv::rectangle(f.rgb, cv::Rect(x + 5, 262, 25, 150), cv::Scalar(30, 30, 30), -1);
  }
  f.depth = cv::Mat(480, 640, CV_32F, cv::Scalar(3.0f));
  return f;
}

void BM_Hog(benchmark::State& state) {
  pf2::HogDetector::Options o;
  o.image_scale = state.range(0) / 100.0;
  pf2::HogDetector detector(o);
  const pf2::Frame f = frame();
  for (auto _ : state) benchmark::DoNotOptimize(detector.detect(f).people.size());
}
BENCHMARK(BM_Hog)->Arg(100)->Arg(50)->Unit(benchmark::kMillisecond);

void BM_DegradeDetections(benchmark::State& state) {
  pf2::BoxDegradation d;
  d.shrink = 0.1;
  d.shift = 5;
  d.drop_probability = 0.1;
  d.false_positive_rate = 0.2;
  double t = 0;
  for (auto _ : state) {
    pf2::Detections det;
    det.timestamp = (t += 1.0 / 30);
    det.people.resize(3);
    for (auto& p : det.people) p.box = pf2::PersonBox{100, 100, 200, 400};
    pf2::degradeDetections(d, cv::Size(640, 480), &det);
    benchmark::DoNotOptimize(det.people.size());
  }
}
BENCHMARK(BM_DegradeDetections);

}  // namespace

BENCHMARK_MAIN();
