// Decoding one recorded frame's PNGs (the first Bonn crowd frame when the shared data is present,
// otherwise a 640x480 image of smooth gradients and noise encoded here): cv::imdecode (argument 0)
// against decodeDatasetPng (1, what pf2::readImageFile uses). Colour then depth.
#include <benchmark/benchmark.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "png_decoder.h"

namespace {

// The first file a TUM list names, or empty.
std::vector<unsigned char> firstListedFile(const std::string& folder, const std::string& list) {
  std::ifstream in(folder + "/" + list);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::ifstream file(folder + "/" + line.substr(line.find(' ') + 1), std::ios::binary);
    return std::vector<unsigned char>((std::istreambuf_iterator<char>(file)), {});
  }
  return {};
}

std::vector<unsigned char> benchPng(bool colour) {
  const std::string folder = std::string(PF2_SHARED_DATA) + "/bonn_crowd_250_150";
  std::vector<unsigned char> png = firstListedFile(folder, colour ? "rgb.txt" : "depth.txt");
  if (!png.empty()) return png;
  cv::Mat image(480, 640, colour ? CV_8UC3 : CV_16UC1);
  cv::randn(image, cv::Scalar::all(colour ? 128 : 20000), cv::Scalar::all(colour ? 4 : 200));
  for (int v = 0; v < image.rows; ++v) image.row(v) += cv::Scalar::all(colour ? v / 4 : 10 * v);
  cv::imencode(".png", image, png);
  return png;
}

void BM_DecodeColourPng(benchmark::State& s) {
  const std::vector<unsigned char> png = benchPng(true);
  for (auto _ : s) {
    cv::Mat image = s.range(0) == 0 ? cv::imdecode(png, cv::IMREAD_COLOR) : pf2::decodeDatasetPng(png, cv::IMREAD_COLOR);
    benchmark::DoNotOptimize(image.data);
  }
}
BENCHMARK(BM_DecodeColourPng)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

void BM_DecodeDepthPng(benchmark::State& s) {
  const std::vector<unsigned char> png = benchPng(false);
  for (auto _ : s) {
    cv::Mat image =
        s.range(0) == 0 ? cv::imdecode(png, cv::IMREAD_UNCHANGED) : pf2::decodeDatasetPng(png, cv::IMREAD_UNCHANGED);
    benchmark::DoNotOptimize(image.data);
  }
}
BENCHMARK(BM_DecodeDepthPng)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
