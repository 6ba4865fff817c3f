#pragma once
// TensorFlow.js graph models (model.json + .bin weight shards) run without TensorFlow: the graph is
// re-encoded as a TensorFlow GraphDef (protobuf wire format, written here by hand) and handed to
// OpenCV's DNN importer. On the way, quantised weights (uint8/uint16 affine, float16) become
// float32, and the fused ops TF.js graphs carry (_FusedConv2D, FusedDepthwiseConv2dNative with
// BiasAdd and an activation) are split into the plain ops OpenCV knows.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

namespace pf2 {

class TfjsGraph {
 public:
  struct Options {
    // Nodes replaced by a float32 Placeholder of the given NHWC shape; what only fed them is
    // dropped. Used to cut pre-processing OpenCV cannot run (MoveNet's int32 input and Cast) and
    // do it in C++ instead. Empty: the model's own Placeholders stay.
    std::map<std::string, std::vector<int>> new_inputs;
    // Nodes the caller reads; only what they depend on is kept, which cuts post-processing OpenCV
    // lacks (ArgMax, GatherNd, TopKV2). Empty: every node is kept.
    std::vector<std::string> outputs;
    // Rewrites that keep the model's function and suit OpenCV's layers better (loadNet only; the
    // speed-up is measured in pf2_learned_detection_bench): x * relu6(x + 3) * (1/6) becomes one
    // HardSwish layer instead of four passes over the tensor, and a tensor times a per-channel
    // vector (squeeze-and-excitation) a Scale layer instead of OpenCV's slow broadcasting product.
    // HardSwish uses 1/6 exactly where TF.js stored it as float16 (0.16663): on a real frame the
    // selfie model's probabilities move by 2e-4 on average, at most 0.04 (at mask edges).
    bool fuse_layers = true;
    // Nodes that pass their first input through unchanged for the shapes of new_inputs, e.g. a
    // crop to the size the tensor already has or a broadcast of a state fed at its full shape:
    // their readers read that input instead, and what only they used (the shape arithmetic
    // OpenCV cannot import) falls away.
    std::vector<std::string> bypass;
    // Factor on the output size of every ResizeBilinear / ResizeNearestNeighbor whose size is a
    // constant, in (0, 4]: a fully convolutional model whose upsamplings were exported with fixed
    // sizes then runs at this factor times its input size (its input fed at that size). 1 = as
    // exported.
    double resize_scale = 1.0;
  };

  // Reads model.json and the weight shards it names (paths relative to model.json). Throws
  // pf2::Error naming the file on anything missing, malformed or unsupported.
  explicit TfjsGraph(const std::string& model_json_path);
  ~TfjsGraph();
  TfjsGraph(TfjsGraph&&) noexcept;
  TfjsGraph& operator=(TfjsGraph&&) noexcept;

  // The GraphDef's serialised bytes, with the hard-swish fusion when options.fuse_layers (the
  // per-channel products need the network's shapes: loadNet only). Thread safe (const, no shared
  // state).
  std::string toGraphDef(const Options& options) const;
  // toGraphDef read by cv::dnn::readNetFromTensorflow, CPU backend. Thread safe.
  cv::dnn::Net loadNet(const Options& options) const;

  // The dequantised value of a Const node, flattened to one CV_32F row (int32 and bool constants
  // are converted). Lets a backend read the model's own normalisation constants. Throws
  // pf2::Error if there is no such constant. Thread safe.
  cv::Mat constant(const std::string& name) const;
  // Whether a node of this name exists. Thread safe.
  bool hasNode(const std::string& name) const;
  // The name of the OpenCV layer that holds a node's output, for Net::forward. Differs from the
  // node name only for a fused convolution without activation: OpenCV merges conv + BiasAdd into
  // one layer named after the convolution. Thread safe.
  std::string layerName(const std::string& node) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pf2
