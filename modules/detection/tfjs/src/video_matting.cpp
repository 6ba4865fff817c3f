#include "pf2/detection/video_matting.h"

#include <array>
#include <vector>

#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"
#include "pf2/detection/learned_models.h"
#include "pf2/detection/tfjs_graph.h"

namespace pf2 {
namespace {

const std::string kScope = "StatefulPartitionedCall/matting_network_wrapper/StatefulPartitionedCall/";
// The source image after the (skipped) downsampling branch: RGB in [0, 1], NHWC.
const std::string kSource = kScope + "cond/output/_660";
// The last convolution: foreground residual (3 channels) and alpha (1), before clamping.
const std::string kHead = kScope + "conv2d_62/BiasAdd";

// One recurrent state of the decoder: its input placeholder, the node computing its next value,
// its channels and the stride of its resolution.
struct State {
  const char* input;
  const char* output;
  int channels;
  int stride;
};
const std::array<State, 4> kStates = {{
    {"r1i", "recurrent_decoder/upsampling_block_2/conv_gru_3/add", 16, 2},
    {"r2i", "recurrent_decoder/upsampling_block_1/conv_gru_2/add", 20, 4},
    {"r3i", "recurrent_decoder/upsampling_block/conv_gru_1/add", 40, 8},
    {"r4i", "recurrent_decoder/bottleneck_block/conv_gru/add", 64, 16},
}};

// Nodes that pass their first input through at a size divisible by 16: each ConvGRU broadcasts
// its state to the features' shape (fed at that shape here), each upsampling crops to the skip
// connection's size (equal here).
std::vector<std::string> bypassedNodes() {
  std::vector<std::string> nodes;
  for (const char* gru : {"recurrent_decoder/bottleneck_block/conv_gru", "recurrent_decoder/upsampling_block/conv_gru_1",
                          "recurrent_decoder/upsampling_block_1/conv_gru_2",
                          "recurrent_decoder/upsampling_block_2/conv_gru_3"})
    nodes.push_back(kScope + gru + "/BroadcastTo");
  for (const char* block : {"upsampling_block", "upsampling_block_1", "upsampling_block_2", "output_block"})
    nodes.push_back(kScope + "recurrent_decoder/" + block + "/crop_to_bounding_box/Slice");
  return nodes;
}

}  // namespace

struct VideoMatting::Impl {
  Options options;
  cv::dnn::Net net;
  std::vector<std::string> output_names;  // kHead, then the states' next values
  std::vector<cv::Mat> states;            // NCHW, zeros after reset()
  bool fresh = true;                      // no frame seen since reset(): warm the state up
};

VideoMatting::VideoMatting(const Options& options) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.options = options;
  if (m.options.model_json.empty()) m.options.model_json = humanModelPath("rvm");
  const int w = m.options.input_width, h = m.options.input_height;
  if (w < 32 || h < 32 || w > 1920 || h > 1920 || w % 16 || h % 16)
    throw Error("VideoMatting: input " + std::to_string(w) + "x" + std::to_string(h) +
                " must be multiples of 16 in [32, 1920]");
  if (m.options.warmup_passes < 0 || m.options.warmup_passes > 10)
    throw Error("VideoMatting: warmup_passes " + std::to_string(m.options.warmup_passes) + " must be in [0, 10]");
  const TfjsGraph graph(m.options.model_json);
  TfjsGraph::Options cut;
  cut.new_inputs[kSource] = {1, h, w, 3};
  for (const State& s : kStates) cut.new_inputs[s.input] = {1, h / s.stride, w / s.stride, s.channels};
  cut.outputs = {kHead};
  for (const State& s : kStates) cut.outputs.push_back(kScope + s.output);
  cut.bypass = bypassedNodes();
  m.net = graph.loadNet(cut);
  for (const std::string& node : cut.outputs) m.output_names.push_back(graph.layerName(node));
  reset();
}

VideoMatting::~VideoMatting() = default;

void VideoMatting::reset() {
  Impl& m = *impl_;
  m.states.clear();
  for (const State& s : kStates) {
    const int shape[] = {1, s.channels, m.options.input_height / s.stride, m.options.input_width / s.stride};
    m.states.emplace_back(4, shape, CV_32F, cv::Scalar(0));
  }
  m.fresh = true;
}

cv::Mat VideoMatting::alpha(const cv::Mat& bgr) {
  if (bgr.empty() || bgr.type() != CV_8UC3) throw Error("VideoMatting: expected a non-empty BGR (CV_8UC3) image");
  Impl& m = *impl_;
  cv::Mat small;
  cv::resize(bgr, small, cv::Size(m.options.input_width, m.options.input_height), 0, 0, cv::INTER_AREA);
  const cv::Mat blob = cv::dnn::blobFromImage(small, 1.0 / 255.0, cv::Size(), cv::Scalar(), true, false);
  const int passes = m.fresh ? 1 + m.options.warmup_passes : 1;
  m.fresh = false;
  std::vector<cv::Mat> outputs;
  for (int pass = 0; pass < passes; ++pass) {
    m.net.setInput(blob, kSource);
    for (size_t i = 0; i < kStates.size(); ++i) m.net.setInput(m.states[i], kStates[i].input);
    m.net.forward(outputs, m.output_names);
    for (size_t i = 0; i < kStates.size(); ++i) m.states[i] = outputs[i + 1].clone();
  }
  // Channel 3 of the head is alpha.
  const cv::Mat head_alpha(m.options.input_height, m.options.input_width, CV_32F, outputs[0].ptr<float>(0, 3));
  cv::Mat clamped, full;
  cv::min(cv::max(head_alpha, 0.0), 1.0, clamped);
  cv::resize(clamped, full, bgr.size(), 0, 0, cv::INTER_LINEAR);
  return full;
}

}  // namespace pf2
