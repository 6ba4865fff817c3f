#include "pf2/detection/tfjs_graph.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

// Base64 of the attribute strings the tiny graphs use (protobuf JSON writes bytes as base64).
const char* kSame = "U0FNRQ==";
const char* kNhwc = "TkhXQw==";
const char* kBiasAdd = "Qmlhc0FkZA==";
const char* kRelu6 = "UmVsdTY=";
const char* kRelu = "UmVsdQ==";

constexpr int kH = 6, kW = 5, kCin = 2, kCout = 3, kK = 3;

// A small graph written the way the TF.js converter writes one: weights in one shard, the conv
// filter quantised to uint8 (min/scale), the biases to float16, the depthwise filter float32.
struct TinyModel {
  std::vector<float> filter;     // HWIO, kK x kK x kCin x kCout, as the model holds it (dequantised)
  std::vector<float> bias;       // kCout, dequantised
  std::vector<float> dw_filter;  // kK x kK x kCout x 1
  std::vector<float> dw_bias;    // kCout
  std::string json_path;
};

float pseudoRandom(int i) { return static_cast<float>(std::sin(12.9898 * i + 1.0) * 2.0); }

std::string nodeJson(const std::string& name, const std::string& op, const std::string& inputs,
                     const std::string& attrs) {
  return "{\"name\":\"" + name + "\",\"op\":\"" + op + "\",\"input\":[" + inputs + "],\"attr\":{" + attrs + "}}";
}

std::string constJson(const std::string& name, const std::string& dtype) {
  return nodeJson(name, "Const", "",
                  "\"value\":{\"tensor\":{\"dtype\":\"" + dtype + "\"}},\"dtype\":{\"type\":\"" + dtype + "\"}");
}

std::string convAttrs(const std::string& fused_ops) {
  return std::string("\"T\":{\"type\":\"DT_FLOAT\"},\"strides\":{\"list\":{\"i\":[\"1\",\"1\",\"1\",\"1\"]}},") +
         "\"padding\":{\"s\":\"" + kSame + "\"},\"data_format\":{\"s\":\"" + kNhwc + "\"}," +
         "\"dilations\":{\"list\":{\"i\":[\"1\",\"1\",\"1\",\"1\"]}},\"explicit_paddings\":{\"list\":{}}," +
         "\"num_args\":{\"i\":\"1\"},\"epsilon\":{\"f\":0},\"fused_ops\":{\"list\":{\"s\":[" + fused_ops + "]}}";
}

std::string quoted(const char* s) { return std::string("\"") + s + "\""; }

// extra_nodes: more node JSON to append (after a comma); extra_weights likewise for the manifest,
// with extra_bytes appended to the shard.
TinyModel writeTinyModel(const std::string& name, const std::string& extra_nodes = "",
                         const std::string& extra_weights = "", const std::string& extra_bytes = "") {
  const std::string dir = testing::TempDir() + name;
  ::mkdir(dir.c_str(), 0755);
  TinyModel m;
  m.json_path = dir + "/model.json";
  std::string shard;

  // Conv filter, uint8: value = q * scale + min.
  const float fmin = -2.0f, fscale = 4.0f / 255.0f;
  for (int i = 0; i < kK * kK * kCin * kCout; ++i) {
    const int q = std::clamp(static_cast<int>(std::lround((pseudoRandom(i) - fmin) / fscale)), 0, 255);
    shard.push_back(static_cast<char>(q));
    m.filter.push_back(q * fscale + fmin);
  }
  // Biases, float16 (OpenCV's own half conversion, independent of the converter's).
  auto addHalf = [&shard](const std::vector<float>& values, std::vector<float>& dequantised) {
    cv::Mat f(1, static_cast<int>(values.size()), CV_32F, const_cast<float*>(values.data())), h, back;
    f.convertTo(h, CV_16F);
    h.convertTo(back, CV_32F);
    shard.append(reinterpret_cast<const char*>(h.data), values.size() * 2);
    dequantised.assign(back.begin<float>(), back.end<float>());
  };
  addHalf({0.5f, -1.25f, 3.0f}, m.bias);
  // Depthwise filter, plain float32.
  for (int i = 0; i < kK * kK * kCout; ++i) {
    const float v = 0.3f * pseudoRandom(100 + i);
    m.dw_filter.push_back(v);
    shard.append(reinterpret_cast<const char*>(&v), 4);
  }
  addHalf({-0.5f, 0.25f, 1.0f}, m.dw_bias);
  shard += extra_bytes;

  std::ofstream(dir + "/tiny.bin", std::ios::binary) << shard;
  std::ostringstream json;
  json << std::setprecision(9);  // min and scale exactly as the test dequantises them
  json << "{\"format\":\"graph-model\",\"modelTopology\":{\"node\":["
       << nodeJson("input", "Placeholder", "",
                   "\"dtype\":{\"type\":\"DT_FLOAT\"},\"shape\":{\"shape\":{\"dim\":[{\"size\":\"1\"},{\"size\":\"" +
                       std::to_string(kH) + "\"},{\"size\":\"" + std::to_string(kW) + "\"},{\"size\":\"" +
                       std::to_string(kCin) + "\"}]}}")
       << "," << constJson("conv/filter", "DT_FLOAT") << "," << constJson("conv/bias", "DT_FLOAT") << ","
       << constJson("dw/filter", "DT_FLOAT") << "," << constJson("dw/bias", "DT_FLOAT") << ","
       << nodeJson("conv/Relu6", "_FusedConv2D", "\"input\",\"conv/filter\",\"conv/bias\"",
                   convAttrs(quoted(kBiasAdd) + "," + quoted(kRelu6)))
       << ","
       << nodeJson("dw/Relu", "FusedDepthwiseConv2dNative", "\"conv/Relu6\",\"dw/filter\",\"dw/bias\"",
                   convAttrs(quoted(kBiasAdd) + "," + quoted(kRelu)))
       << extra_nodes << "]},\"weightsManifest\":[{\"paths\":[\"tiny.bin\"],\"weights\":["
       << "{\"name\":\"conv/filter\",\"shape\":[" << kK << "," << kK << "," << kCin << "," << kCout
       << "],\"dtype\":\"float32\",\"quantization\":{\"dtype\":\"uint8\",\"min\":" << fmin << ",\"scale\":"
       << fscale << "}},"
       << "{\"name\":\"conv/bias\",\"shape\":[" << kCout
       << "],\"dtype\":\"float32\",\"quantization\":{\"dtype\":\"float16\",\"original_dtype\":\"float32\"}},"
       << "{\"name\":\"dw/filter\",\"shape\":[" << kK << "," << kK << "," << kCout << ",1],\"dtype\":\"float32\"},"
       << "{\"name\":\"dw/bias\",\"shape\":[" << kCout
       << "],\"dtype\":\"float32\",\"quantization\":{\"dtype\":\"float16\",\"original_dtype\":\"float32\"}}"
       << extra_weights << "]}]}";
  std::ofstream(m.json_path) << json.str();
  return m;
}

// NHWC input with values in [-2, 2].
std::vector<float> makeInput() {
  std::vector<float> x(kH * kW * kCin);
  for (size_t i = 0; i < x.size(); ++i) x[i] = pseudoRandom(1000 + static_cast<int>(i));
  return x;
}

// The same network computed directly: SAME padding, stride 1, NHWC; returns NHWC.
std::vector<float> directForward(const TinyModel& m, const std::vector<float>& x, float* max_pre_relu6) {
  std::vector<float> a(kH * kW * kCout), out(kH * kW * kCout);
  *max_pre_relu6 = -1e9f;
  for (int y = 0; y < kH; ++y)
    for (int u = 0; u < kW; ++u)
      for (int o = 0; o < kCout; ++o) {
        float s = m.bias[o];
        for (int ky = 0; ky < kK; ++ky)
          for (int kx = 0; kx < kK; ++kx) {
            const int yy = y + ky - 1, uu = u + kx - 1;
            if (yy < 0 || yy >= kH || uu < 0 || uu >= kW) continue;
            for (int c = 0; c < kCin; ++c)
              s += x[(yy * kW + uu) * kCin + c] * m.filter[((ky * kK + kx) * kCin + c) * kCout + o];
          }
        *max_pre_relu6 = std::max(*max_pre_relu6, s);
        a[(y * kW + u) * kCout + o] = std::min(std::max(s, 0.f), 6.f);
      }
  for (int y = 0; y < kH; ++y)
    for (int u = 0; u < kW; ++u)
      for (int o = 0; o < kCout; ++o) {
        float s = m.dw_bias[o];
        for (int ky = 0; ky < kK; ++ky)
          for (int kx = 0; kx < kK; ++kx) {
            const int yy = y + ky - 1, uu = u + kx - 1;
            if (yy < 0 || yy >= kH || uu < 0 || uu >= kW) continue;
            s += a[(yy * kW + uu) * kCout + o] * m.dw_filter[(ky * kK + kx) * kCout + o];
          }
        out[(y * kW + u) * kCout + o] = std::max(s, 0.f);
      }
  return out;
}

// Runs the net on an NHWC input; returns the output converted back to NHWC.
std::vector<float> runNet(cv::dnn::Net& net, const std::vector<float>& x, const std::string& output) {
  const int in_shape[] = {1, kCin, kH, kW};
  cv::Mat blob(4, in_shape, CV_32F);
  for (int y = 0; y < kH; ++y)
    for (int u = 0; u < kW; ++u)
      for (int c = 0; c < kCin; ++c) blob.ptr<float>(0, c)[y * kW + u] = x[(y * kW + u) * kCin + c];
  net.setInput(blob);
  const cv::Mat out = net.forward(output);
  EXPECT_EQ(out.dims, 4);
  EXPECT_EQ(out.size[1], kCout);
  EXPECT_EQ(out.size[2], kH);
  EXPECT_EQ(out.size[3], kW);
  std::vector<float> nhwc(kH * kW * kCout);
  for (int y = 0; y < kH; ++y)
    for (int u = 0; u < kW; ++u)
      for (int o = 0; o < kCout; ++o) nhwc[(y * kW + u) * kCout + o] = out.ptr<float>(0, o)[y * kW + u];
  return nhwc;
}

TEST(TfjsGraph, FusedQuantisedGraphMatchesDirectComputation) {
  const TinyModel m = writeTinyModel("pf2_tfjs_tiny");
  const TfjsGraph graph(m.json_path);
  cv::dnn::Net net = graph.loadNet({});
  const std::vector<float> x = makeInput();
  float max_pre_relu6 = 0;
  const std::vector<float> expected = directForward(m, x, &max_pre_relu6);
  const std::vector<float> got = runNet(net, x, "dw/Relu");
  ASSERT_EQ(got.size(), expected.size());
  int zeros = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_NEAR(got[i], expected[i], 1e-4f) << "element " << i;
    zeros += expected[i] == 0.f;
  }
  // The data must exercise both activations, or the comparison would not test them.
  EXPECT_GT(max_pre_relu6, 6.f);
  EXPECT_GT(zeros, 0);
  EXPECT_LT(zeros, static_cast<int>(got.size()));
}

TEST(TfjsGraph, ConstantsAreDequantised) {
  const TinyModel m = writeTinyModel("pf2_tfjs_const");
  const TfjsGraph graph(m.json_path);
  const cv::Mat filter = graph.constant("conv/filter");
  ASSERT_EQ(filter.total(), m.filter.size());
  for (size_t i = 0; i < m.filter.size(); ++i) EXPECT_NEAR(filter.at<float>(static_cast<int>(i)), m.filter[i], 1e-6f);
  const cv::Mat bias = graph.constant("conv/bias");
  ASSERT_EQ(bias.total(), 3u);
  EXPECT_FLOAT_EQ(bias.at<float>(1), -1.25f);  // exactly representable in float16
  EXPECT_TRUE(graph.hasNode("dw/Relu"));
  EXPECT_FALSE(graph.hasNode("nothing"));
  EXPECT_THROW(graph.constant("nothing"), Error);
}

// An int32 pre-processing Cast in front and an ArgMax behind, as in MoveNet: the cut graph (float
// input at the conv, output at the depthwise) holds neither and still computes the same values.
TEST(TfjsGraph, CutsInputsAndOutputs) {
  const std::string extra =
      "," + nodeJson("raw", "Placeholder", "", "\"dtype\":{\"type\":\"DT_INT32\"}") + "," +
      nodeJson("cast", "Cast", "\"raw\"",
               "\"SrcT\":{\"type\":\"DT_INT32\"},\"DstT\":{\"type\":\"DT_FLOAT\"},\"Truncate\":{\"b\":false}") +
      "," + constJson("argmax/dim", "DT_INT32") + "," +
      nodeJson("argmax", "ArgMax", "\"dw/Relu\",\"argmax/dim\"",
               "\"T\":{\"type\":\"DT_FLOAT\"},\"Tidx\":{\"type\":\"DT_INT32\"},\"output_type\":{\"type\":\"DT_INT64\"}");
  const int32_t dim = 3;
  const TinyModel m = writeTinyModel("pf2_tfjs_cut", extra,
                                     ",{\"name\":\"argmax/dim\",\"shape\":[],\"dtype\":\"int32\"}",
                                     std::string(reinterpret_cast<const char*>(&dim), 4));
  const TfjsGraph graph(m.json_path);
  EXPECT_FLOAT_EQ(graph.constant("argmax/dim").at<float>(0), 3.f);
  const std::string whole = graph.toGraphDef({});
  EXPECT_NE(whole.find("ArgMax"), std::string::npos);

  TfjsGraph::Options options;
  options.new_inputs["input"] = {1, kH, kW, kCin};
  options.outputs = {"dw/Relu"};
  const std::string cut = graph.toGraphDef(options);
  EXPECT_EQ(cut.find("ArgMax"), std::string::npos);
  EXPECT_EQ(cut.find("Cast"), std::string::npos);
  EXPECT_NE(cut.find("DepthwiseConv2dNative"), std::string::npos);
  cv::dnn::Net net = graph.loadNet(options);
  const std::vector<float> x = makeInput();
  float max_pre_relu6 = 0;
  const std::vector<float> expected = directForward(m, x, &max_pre_relu6);
  const std::vector<float> got = runNet(net, x, "dw/Relu");
  for (size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], expected[i], 1e-4f) << "element " << i;

  options.outputs = {"no/such/node"};
  EXPECT_THROW(graph.toGraphDef(options), Error);
}

// Shape arithmetic OpenCV cannot import, guarding a node that passes its input through at the
// shapes given: bypassed, it falls away, and so does what only a control dependency reaches.
TEST(TfjsGraph, BypassedNodesAndControlDependenciesFallAway) {
  const std::string t = "\"T\":{\"type\":\"DT_FLOAT\"}";
  const std::string extra =
      "," + nodeJson("shape", "Shape", "\"conv/Relu6\"", t + ",\"out_type\":{\"type\":\"DT_INT32\"}") + "," +
      nodeJson("bcast", "BroadcastTo", "\"dw/Relu\",\"shape\"", t + ",\"Tidx\":{\"type\":\"DT_INT32\"}") + "," +
      nodeJson("out", "Relu", "\"bcast\",\"^shape\"", t);
  const TinyModel m = writeTinyModel("pf2_tfjs_bypass", extra);
  const TfjsGraph graph(m.json_path);
  TfjsGraph::Options options;
  options.outputs = {"out"};
  EXPECT_NE(graph.toGraphDef(options).find("BroadcastTo"), std::string::npos);
  options.bypass = {"bcast"};
  const std::string cut = graph.toGraphDef(options);
  EXPECT_EQ(cut.find("BroadcastTo"), std::string::npos);
  EXPECT_EQ(cut.find("Shape"), std::string::npos);
  cv::dnn::Net net = graph.loadNet(options);
  const std::vector<float> x = makeInput();
  float max_pre_relu6 = 0;
  const std::vector<float> expected = directForward(m, x, &max_pre_relu6);  // >= 0: Relu keeps it
  const std::vector<float> got = runNet(net, x, "out");
  for (size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], expected[i], 1e-4f) << "element " << i;

  options.bypass = {"no/such/node"};
  EXPECT_THROW(graph.toGraphDef(options), Error);
}

// 1 - x, as a ConvGRU writes it: OpenCV 4.6 alone would compute x - 1.
TEST(TfjsGraph, ConstantMinusTensorKeepsItsSign) {
  const std::string t = "\"T\":{\"type\":\"DT_FLOAT\"}";
  const float one = 1.f;
  const TinyModel m = writeTinyModel("pf2_tfjs_sub", "," + constJson("one", "DT_FLOAT") + "," +
                                                         nodeJson("one_minus", "Sub", "\"one\",\"dw/Relu\"", t),
                                     ",{\"name\":\"one\",\"shape\":[],\"dtype\":\"float32\"}",
                                     std::string(reinterpret_cast<const char*>(&one), 4));
  const TfjsGraph graph(m.json_path);
  TfjsGraph::Options options;
  options.outputs = {"one_minus"};
  cv::dnn::Net net = graph.loadNet(options);
  const std::vector<float> x = makeInput();
  float max_pre_relu6 = 0;
  const std::vector<float> y = directForward(m, x, &max_pre_relu6);
  const std::vector<float> got = runNet(net, x, "one_minus");
  for (size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], 1.f - y[i], 1e-4f) << "element " << i;
}

// An upsampling exported with a fixed size (twice the tiny graph's output) run at half that
// size, as a fully convolutional model is run at a smaller input: the resize's constant size
// scales with resize_scale, so here it resizes to the size it has, which changes nothing.
TEST(TfjsGraph, ResizeScaleScalesConstantResizeSizes) {
  const std::string t = "\"T\":{\"type\":\"DT_FLOAT\"}";
  const int32_t size[2] = {2 * kH, 2 * kW};
  const TinyModel m = writeTinyModel(
      "pf2_tfjs_resize",
      "," + constJson("up/size", "DT_INT32") + "," +
          nodeJson("up", "ResizeBilinear", "\"dw/Relu\",\"up/size\"",
                   t + ",\"align_corners\":{\"b\":false},\"half_pixel_centers\":{\"b\":true}"),
      ",{\"name\":\"up/size\",\"shape\":[2],\"dtype\":\"int32\"}",
      std::string(reinterpret_cast<const char*>(size), sizeof(size)));
  const TfjsGraph graph(m.json_path);
  TfjsGraph::Options options;
  options.outputs = {"up"};
  const std::vector<float> x = makeInput();
  {
    cv::dnn::Net as_exported = graph.loadNet(options);
    const int in_shape[] = {1, kCin, kH, kW};
    as_exported.setInput(cv::Mat(4, in_shape, CV_32F, cv::Scalar(0.5)));
    const cv::Mat out = as_exported.forward("up");
    ASSERT_EQ(out.dims, 4);
    EXPECT_EQ(out.size[2], 2 * kH);
    EXPECT_EQ(out.size[3], 2 * kW);
  }
  options.resize_scale = 0.5;
  cv::dnn::Net half = graph.loadNet(options);
  float max_pre_relu6 = 0;
  const std::vector<float> expected = directForward(m, x, &max_pre_relu6);
  const std::vector<float> got = runNet(half, x, "up");
  for (size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], expected[i], 1e-4f) << "element " << i;

  options.resize_scale = 0.0;
  EXPECT_THROW(graph.loadNet(options), Error);
}

// MobileNetV3's blocks as TF.js writes them behind the tiny graph: a hard-swish chain
// Mul(Mul(1/6, x), Relu6(x + 3)), a squeeze-and-excitation product (x times the sigmoid of its
// channel means), and a look-alike chain with + 2 that is not a hard-swish.
std::string mobileNetV3Nodes() {
  const std::string pool_attrs =
      "\"T\":{\"type\":\"DT_FLOAT\"},\"ksize\":{\"list\":{\"i\":[\"1\",\"" + std::to_string(kH) + "\",\"" +
      std::to_string(kW) + "\",\"1\"]}},\"strides\":{\"list\":{\"i\":[\"1\",\"" + std::to_string(kH) + "\",\"" +
      std::to_string(kW) + "\",\"1\"]}},\"padding\":{\"s\":\"VkFMSUQ=\"},\"data_format\":{\"s\":\"" + kNhwc + "\"}";
  const std::string t = "\"T\":{\"type\":\"DT_FLOAT\"}";
  return "," + constJson("sixth", "DT_FLOAT") + "," + constJson("three", "DT_FLOAT") + "," +
         constJson("two", "DT_FLOAT") + "," + nodeJson("hs/mul", "Mul", "\"sixth\",\"dw/Relu\"", t) + "," +
         nodeJson("hs/add", "AddV2", "\"dw/Relu\",\"three\"", t) + "," + nodeJson("hs/relu6", "Relu6", "\"hs/add\"", t) +
         "," + nodeJson("hs/out", "Mul", "\"hs/mul\",\"hs/relu6\"", t) + "," +
         nodeJson("se/pool", "AvgPool", "\"hs/out\"", pool_attrs) + "," +
         nodeJson("se/sigmoid", "Sigmoid", "\"se/pool\"", t) + "," +
         nodeJson("se/out", "Mul", "\"hs/out\",\"se/sigmoid\"", t) + "," +
         nodeJson("not/mul", "Mul", "\"sixth\",\"se/out\"", t) + "," +
         nodeJson("not/add", "AddV2", "\"se/out\",\"two\"", t) + "," + nodeJson("not/relu6", "Relu6", "\"not/add\"", t) +
         "," + nodeJson("not/out", "Mul", "\"not/mul\",\"not/relu6\"", t);
}

// mobileNetV3Nodes() computed directly on the tiny graph's NHWC output y.
std::vector<float> mobileNetV3Direct(const std::vector<float>& y) {
  const auto relu6 = [](float v) { return std::min(std::max(v, 0.f), 6.f); };
  std::vector<float> hs(y.size()), mean(kCout, 0.f), out(y.size());
  for (size_t i = 0; i < y.size(); ++i) {
    hs[i] = y[i] * relu6(y[i] + 3.f) / 6.f;
    mean[i % kCout] += hs[i] / (kH * kW);
  }
  for (size_t i = 0; i < y.size(); ++i) {
    const float se = hs[i] / (1.f + std::exp(-mean[i % kCout]));
    out[i] = se * relu6(se + 2.f) / 6.f;
  }
  return out;
}

int layersOfType(cv::dnn::Net& net, const std::string& type) {
  int count = 0;
  for (const std::string& name : net.getLayerNames()) count += net.getLayer(name)->type == type;
  return count;
}

TEST(TfjsGraph, FusedHardSwishAndChannelScaleComputeTheSame) {
  const float constants[] = {1.f / 6.f, 3.f, 2.f};
  const TinyModel m = writeTinyModel(
      "pf2_tfjs_mobilenetv3", mobileNetV3Nodes(),
      ",{\"name\":\"sixth\",\"shape\":[],\"dtype\":\"float32\"},{\"name\":\"three\",\"shape\":[],\"dtype\":"
      "\"float32\"},{\"name\":\"two\",\"shape\":[],\"dtype\":\"float32\"}",
      std::string(reinterpret_cast<const char*>(constants), sizeof(constants)));
  const TfjsGraph graph(m.json_path);
  const std::vector<float> x = makeInput();
  float max_pre_relu6 = 0;
  const std::vector<float> expected = mobileNetV3Direct(directForward(m, x, &max_pre_relu6));

  TfjsGraph::Options plain;
  plain.fuse_layers = false;
  for (const TfjsGraph::Options& options : {plain, TfjsGraph::Options()}) {
    cv::dnn::Net net = graph.loadNet(options);
    const std::vector<float> got = runNet(net, x, "not/out");
    for (size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], expected[i], 1e-4f) << "element " << i;
    // Fused: the hard-swish is one layer (its three inner nodes gone), the look-alike is not; the
    // channel product is a Scale layer.
    EXPECT_EQ(layersOfType(net, "HardSwish"), options.fuse_layers ? 1 : 0);
    EXPECT_EQ(net.getLayer("se/out")->type, options.fuse_layers ? "Scale" : "Eltwise");
    EXPECT_EQ(net.getLayer("not/out")->type, "Eltwise");
    EXPECT_EQ(net.getLayerId("hs/relu6") >= 0, !options.fuse_layers);
  }
}

TEST(TfjsGraph, BadFilesThrowWithTheFileName) {
  const std::string dir = testing::TempDir();
  EXPECT_THROW(TfjsGraph(dir + "pf2_tfjs_missing/model.json"), Error);

  const std::string bad_json = dir + "pf2_tfjs_bad.json";
  std::ofstream(bad_json) << "{\"format\":\"graph-model\",\"modelTopology\":";
  try {
    TfjsGraph graph(bad_json);
    ADD_FAILURE() << "truncated JSON accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(bad_json), std::string::npos) << e.what();
  }

  // A shard shorter than the manifest says.
  const TinyModel m = writeTinyModel("pf2_tfjs_short");
  std::ofstream(testing::TempDir() + "pf2_tfjs_short/tiny.bin", std::ios::binary) << "abc";
  EXPECT_THROW(TfjsGraph graph(m.json_path), Error);
}

}  // namespace
}  // namespace pf2
