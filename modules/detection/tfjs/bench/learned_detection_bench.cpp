// Per-frame time of the learned detectors on a 640x480 frame (the real TUM fr3/walking_xyz frame
// when the shared data is present, otherwise a synthetic one; the time does not depend on the
// content). Needs the models (scripts/fetch_models.sh); reports an error per benchmark without.
// CPU time counts all threads (OpenCV DNN runs its own, two on two cores); wall is the latency.
#include <benchmark/benchmark.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pf2/detection/crop_segmenter.h"
#include "pf2/detection/learned_models.h"
#include "pf2/detection/learned_person_detector.h"
#include "pf2/detection/movenet_detector.h"
#include "pf2/detection/selfie_segmenter.h"
#include "pf2/detection/tfjs_graph.h"

namespace pf2 {
namespace {

Frame benchFrame() {
  Frame f;
  f.rgb = cv::imread(std::string(PF2_SHARED_DATA) + "/tum_fr3_walking_xyz_1frame/1341846313.553992.png");
  if (f.rgb.empty()) {
    f.rgb = cv::Mat(480, 640, CV_8UC3);
    cv::randu(f.rgb, cv::Scalar::all(0), cv::Scalar::all(255));
  }
  return f;
}

void BM_ConvertSelfieGraph(benchmark::State& state) {
  if (!humanModelAvailable("selfie")) return state.SkipWithError("no model; run scripts/fetch_models.sh");
  for (auto _ : state) {
    cv::dnn::Net net = TfjsGraph(humanModelPath("selfie")).loadNet({});
    benchmark::DoNotOptimize(net);
  }
}
BENCHMARK(BM_ConvertSelfieGraph)->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);

// The selfie network alone, as imported (0) and with TfjsGraph's layer fusion (1, the default).
void BM_SelfieNetwork(benchmark::State& state) {
  if (!humanModelAvailable("selfie")) return state.SkipWithError("no model; run scripts/fetch_models.sh");
  TfjsGraph::Options options;
  options.fuse_layers = state.range(0) != 0;
  cv::dnn::Net net = TfjsGraph(humanModelPath("selfie")).loadNet(options);
  net.setInput(cv::dnn::blobFromImage(benchFrame().rgb, 1.0 / 255.0, cv::Size(256, 256), cv::Scalar(), true, false));
  for (auto _ : state) benchmark::DoNotOptimize(net.forward());
}
BENCHMARK(BM_SelfieNetwork)->Arg(0)->Arg(1)->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);

// Argument: square_crops (0: one stretched run, 1: two square crops).
void BM_Selfie(benchmark::State& state) {
  if (!humanModelAvailable("selfie")) return state.SkipWithError("no model; run scripts/fetch_models.sh");
  SelfieSegmenter::Options options;
  options.square_crops = state.range(0) != 0;
  SelfieSegmenter selfie(options);
  const Frame frame = benchFrame();
  for (auto _ : state) benchmark::DoNotOptimize(selfie.detect(frame));
}
BENCHMARK(BM_Selfie)->Arg(0)->Arg(1)->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);

// Arguments: network input width and height (multiples of 32).
void BM_MoveNet(benchmark::State& state) {
  if (!humanModelAvailable("movenet-multipose")) return state.SkipWithError("no model; run scripts/fetch_models.sh");
  MoveNetDetector::Options options;
  options.input_width = static_cast<int>(state.range(0));
  options.input_height = static_cast<int>(state.range(1));
  MoveNetDetector movenet(options);
  const Frame frame = benchFrame();
  for (auto _ : state) benchmark::DoNotOptimize(movenet.detect(frame));
}
BENCHMARK(BM_MoveNet)->Args({256, 192})->Args({384, 288})->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);

// Argument: pose_every; the time is the mean over the frames, MoveNet runs included.
void BM_Learned(benchmark::State& state) {
  if (!humanModelAvailable("selfie") || !humanModelAvailable("movenet-multipose"))
    return state.SkipWithError("no models; run scripts/fetch_models.sh");
  LearnedPersonDetector::Options options;
  options.pose_every = static_cast<int>(state.range(0));
  LearnedPersonDetector learned(options);
  const Frame frame = benchFrame();
  for (auto _ : state) benchmark::DoNotOptimize(learned.detect(frame));
}
BENCHMARK(BM_Learned)->Arg(1)->Arg(3)->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);

// One crop mask: BlazePose Lite's segmentation of the crop around the first MoveNet person, the
// network's input side as the argument.
void BM_CropSegment(benchmark::State& state) {
  if (!humanModelAvailable("blazepose-lite") || !humanModelAvailable("movenet-multipose"))
    return state.SkipWithError("no models; run scripts/fetch_models.sh");
  const Frame frame = benchFrame();
  MoveNetDetector movenet({});
  const Detections people = movenet.detect(frame);
  if (people.people.empty()) return state.SkipWithError("MoveNet found no one on the frame");
  PersonCropSegmenter::Options options;
  options.input_size = static_cast<int>(state.range(0));
  PersonCropSegmenter segmenter(options);
  for (auto _ : state) benchmark::DoNotOptimize(segmenter.segment(frame.rgb, people.people[0].box));
}
BENCHMARK(BM_CropSegment)->Arg(256)->Arg(224)->Arg(192)->MeasureProcessCPUTime()->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace pf2

BENCHMARK_MAIN();
