#include "pf2/detection/tfjs_graph.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

using Json = nlohmann::json;

// TensorFlow's DataType enum (tensorflow/core/framework/types.proto).
enum DataType : int { kFloat = 1, kInt32 = 3, kBool = 10 };

int dataTypeFromName(const std::string& name) {
  static const std::map<std::string, int> kTypes = {
      {"DT_FLOAT", 1}, {"DT_DOUBLE", 2}, {"DT_INT32", 3}, {"DT_UINT8", 4}, {"DT_INT16", 5},
      {"DT_INT8", 6},  {"DT_STRING", 7}, {"DT_INT64", 9}, {"DT_BOOL", 10}, {"DT_HALF", 19}};
  const auto it = kTypes.find(name);
  if (it == kTypes.end()) throw Error("unknown TensorFlow data type " + name);
  return it->second;
}

// Protocol-buffer wire format, only what GraphDef needs: varints, 32-bit floats and
// length-delimited fields.
class ProtoWriter {
 public:
  void varint(int field, uint64_t value) {
    key(field, 0);
    rawVarint(value);
  }
  void int64(int field, int64_t value) { varint(field, static_cast<uint64_t>(value)); }
  void float32(int field, float value) {
    key(field, 5);
    char bytes[4];
    std::memcpy(bytes, &value, 4);
    out_.append(bytes, 4);
  }
  void bytes(int field, const std::string& value) {
    key(field, 2);
    rawVarint(value.size());
    out_ += value;
  }
  void message(int field, const ProtoWriter& value) { bytes(field, value.out_); }
  // Packed repeated varints (proto3 default for repeated scalars).
  void packedVarints(int field, const std::vector<int64_t>& values) {
    if (values.empty()) return;
    ProtoWriter packed;
    for (int64_t v : values) packed.rawVarint(static_cast<uint64_t>(v));
    bytes(field, packed.out_);
  }
  void packedFloats(int field, const std::vector<float>& values) {
    if (values.empty()) return;
    std::string packed(values.size() * 4, '\0');
    std::memcpy(&packed[0], values.data(), packed.size());
    bytes(field, packed);
  }
  const std::string& str() const { return out_; }

 private:
  void key(int field, int wire_type) { rawVarint((static_cast<uint64_t>(field) << 3) | wire_type); }
  void rawVarint(uint64_t value) {
    while (value >= 0x80) {
      out_.push_back(static_cast<char>((value & 0x7F) | 0x80));
      value >>= 7;
    }
    out_.push_back(static_cast<char>(value));
  }
  std::string out_;
};

std::string base64Decode(const std::string& in) {
  static const std::string kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  uint32_t buffer = 0;
  int bits = 0;
  for (char c : in) {
    if (c == '=') break;
    const size_t v = kAlphabet.find(c);
    if (v == std::string::npos) throw Error("invalid base64 text '" + in + "'");
    buffer = (buffer << 6) | static_cast<uint32_t>(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<char>((buffer >> bits) & 0xFF));
    }
  }
  return out;
}

// TF.js writes int64 attributes as strings ("1") and sometimes as numbers.
int64_t jsonInt(const Json& j) {
  if (j.is_string()) return std::stoll(j.get<std::string>());
  return j.get<int64_t>();
}

float jsonFloat(const Json& j) {
  if (j.is_string()) return std::stof(j.get<std::string>());
  return j.get<float>();
}

struct Tensor {
  int dtype = kFloat;
  std::vector<int64_t> shape;
  std::string data;  // little-endian, float32 / int32 / bool (1 byte) after dequantisation
};

struct Node {
  std::string name, op;
  std::vector<std::string> inputs;
  Json attr;  // the AttrValue map as TF.js's JSON writes it
  std::optional<Tensor> value;  // a Const made by a rewrite (the model's own are in weights)
};

void writeShape(ProtoWriter& shape_proto, const std::vector<int64_t>& dims) {
  for (int64_t d : dims) {
    ProtoWriter dim;
    dim.int64(1, d);
    shape_proto.message(2, dim);
  }
}

ProtoWriter shapeFromJson(const Json& j) {
  ProtoWriter shape;
  std::vector<int64_t> dims;
  if (j.contains("dim"))
    for (const Json& d : j["dim"]) dims.push_back(d.contains("size") ? jsonInt(d["size"]) : 0);
  writeShape(shape, dims);
  if (j.value("unknownRank", false)) shape.varint(3, 1);
  return shape;
}

ProtoWriter tensorProto(const Tensor& t) {
  ProtoWriter tensor, shape;
  tensor.varint(1, static_cast<uint64_t>(t.dtype));
  writeShape(shape, t.shape);
  tensor.message(2, shape);
  if (t.dtype == kInt32 && t.data.size() == 4) {
    // A scalar int32 as int_val: OpenCV reads a Split's axis from there only.
    int32_t v;
    std::memcpy(&v, t.data.data(), 4);
    tensor.packedVarints(7, {static_cast<int64_t>(v)});
  } else if (!t.data.empty()) {
    tensor.bytes(4, t.data);
  }
  return tensor;
}

// One AttrValue from its JSON form (protobuf's JSON mapping: bytes as base64, int64 as strings).
ProtoWriter attrValue(const std::string& key, const Json& j) {
  ProtoWriter value;
  if (j.contains("list")) {
    const Json& l = j["list"];
    ProtoWriter list;
    if (l.contains("s"))
      for (const Json& s : l["s"]) list.bytes(2, base64Decode(s.get<std::string>()));
    if (l.contains("i")) {
      std::vector<int64_t> ints;
      for (const Json& i : l["i"]) ints.push_back(jsonInt(i));
      list.packedVarints(3, ints);
    }
    if (l.contains("f")) {
      std::vector<float> floats;
      for (const Json& f : l["f"]) floats.push_back(jsonFloat(f));
      list.packedFloats(4, floats);
    }
    if (l.contains("b")) {
      std::vector<int64_t> bools;
      for (const Json& b : l["b"]) bools.push_back(b.get<bool>() ? 1 : 0);
      list.packedVarints(5, bools);
    }
    if (l.contains("type")) {
      std::vector<int64_t> types;
      for (const Json& t : l["type"]) types.push_back(dataTypeFromName(t.get<std::string>()));
      list.packedVarints(6, types);
    }
    if (l.contains("shape"))
      for (const Json& s : l["shape"]) list.message(7, shapeFromJson(s));
    value.message(1, list);
  } else if (j.contains("s")) {
    value.bytes(2, base64Decode(j["s"].get<std::string>()));
  } else if (j.contains("i")) {
    value.int64(3, jsonInt(j["i"]));
  } else if (j.contains("f")) {
    value.float32(4, jsonFloat(j["f"]));
  } else if (j.contains("b")) {
    value.varint(5, j["b"].get<bool>() ? 1 : 0);
  } else if (j.contains("type")) {
    value.varint(6, static_cast<uint64_t>(dataTypeFromName(j["type"].get<std::string>())));
  } else if (j.contains("shape")) {
    value.message(7, shapeFromJson(j["shape"]));
  } else {
    throw Error("attribute '" + key + "' of an unsupported kind: " + j.dump());
  }
  return value;
}

void addAttr(ProtoWriter& node, const std::string& key, const ProtoWriter& value) {
  ProtoWriter entry;
  entry.bytes(1, key);
  entry.message(2, value);
  node.message(5, entry);
}

ProtoWriter nodeProto(const std::string& name, const std::string& op,
                      const std::vector<std::string>& inputs) {
  ProtoWriter node;
  node.bytes(1, name);
  node.bytes(2, op);
  for (const std::string& in : inputs) node.bytes(3, in);
  return node;
}

// "name:1" and "^name" both refer to the node "name".
std::string producerOf(const std::string& input) {
  std::string name = input[0] == '^' ? input.substr(1) : input;
  const size_t colon = name.rfind(':');
  if (colon != std::string::npos && name.find_first_not_of("0123456789", colon + 1) == std::string::npos)
    name.resize(colon);
  return name;
}

// The plain convolution split out of a fused node.
std::string convNodeName(const std::string& fused_node) { return fused_node + "/_conv"; }

float halfToFloat(uint16_t h) {
  const uint32_t sign = static_cast<uint32_t>(h & 0x8000) << 16;
  uint32_t exponent = (h >> 10) & 0x1F;
  uint32_t mantissa = h & 0x3FF;
  uint32_t bits;
  if (exponent == 0x1F) {
    bits = sign | 0x7F800000 | (mantissa << 13);  // inf / nan
  } else if (exponent != 0) {
    bits = sign | ((exponent + 112) << 23) | (mantissa << 13);
  } else if (mantissa == 0) {
    bits = sign;
  } else {  // subnormal half: normalise
    exponent = 113;
    while (!(mantissa & 0x400)) {
      mantissa <<= 1;
      --exponent;
    }
    bits = sign | (exponent << 23) | ((mantissa & 0x3FF) << 13);
  }
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

std::string readBinary(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw fileError(path, "cannot open weight shard");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace

struct TfjsGraph::Impl {
  std::string path;
  std::vector<Node> nodes;
  std::unordered_map<std::string, size_t> index;  // node name -> position in nodes
  std::unordered_map<std::string, Tensor> weights;

  void readWeights(const Json& manifest, const std::string& dir);
  void emitNode(ProtoWriter& graph, const Node& n) const;
  // The node a data input names, or nullptr.
  const Node* producer(const std::string& input) const;
  // A float Const node's single value, or NaN.
  float scalar(const std::string& input) const;
  // x when n is the last Mul of x * relu6(x + 3) * (1/6), the form TF.js writes MobileNetV3's
  // hard-swish in: Mul(Mul(1/6, x), Relu6(Add(x, 3))), either order throughout; else empty.
  std::string hardSwishInput(const Node& n) const;
  // Readers of a bypassed node read its first input instead (Options::bypass).
  void bypassNodes(const std::vector<std::string>& bypass, std::vector<Node>* out) const;
  // TF writes a dilated convolution as BatchToSpaceND(conv(SpaceToBatchND(x, block, paddings)),
  // block, crops), with paddings and crops computed from the tensor's shape (they only round its
  // size up to a multiple of the block and back). OpenCV reads the dilation from the block and
  // the convolution's padding from the paddings, and needs both as constants; it drops the
  // BatchToSpaceND. Here both become zeros (appended to out): the model's own padding is an
  // explicit Pad before, which OpenCV keeps.
  void constantDilationPaddings(std::vector<Node>* out) const;
  // Sub(c, x) with c constant: OpenCV 4.6 computes x - c (it negates the constant and adds it
  // to whichever input is not constant), so it becomes AddV2(Mul(x, -1), c) (nodes appended to
  // out). A ConvGRU's 1 - z is written so.
  void constantFirstSubtractions(std::vector<Node>* out) const;
  // The constant sizes of the resizes times factor (Options::resize_scale), rounded; a size
  // constant two resizes share is scaled once.
  void scaledResizes(double factor, std::vector<Node>* out) const;
  // The nodes to emit: a copy with the bypassed nodes skipped, the dilated convolutions'
  // paddings made constant, constant-first subtractions turned round and the fused layers
  // rewritten (channel_scales: Mul node -> the index of its per-channel input).
  std::vector<Node> rewritten(const Options& options, const std::map<std::string, int>& channel_scales) const;
  std::string graphDef(const Options& options, const std::map<std::string, int>& channel_scales) const;
  // The Mul nodes the imported net runs as broadcasting Eltwise products of a tensor and a
  // per-channel vector, with the vector's input index; empty when the input shape is not fixed.
  std::map<std::string, int> channelScales(cv::dnn::Net& net, const Options& options) const;
  cv::dnn::Net importNet(const std::string& graph_def) const;
};

const Node* TfjsGraph::Impl::producer(const std::string& input) const {
  const auto it = index.find(producerOf(input));
  return it == index.end() ? nullptr : &nodes[it->second];
}

float TfjsGraph::Impl::scalar(const std::string& input) const {
  const Node* n = producer(input);
  if (!n || n->op != "Const") return std::numeric_limits<float>::quiet_NaN();
  const auto w = weights.find(n->name);
  if (w == weights.end() || w->second.dtype != kFloat || w->second.data.size() != 4)
    return std::numeric_limits<float>::quiet_NaN();
  float value;
  std::memcpy(&value, w->second.data.data(), 4);
  return value;
}

std::string TfjsGraph::Impl::hardSwishInput(const Node& n) const {
  if (n.op != "Mul" || n.inputs.size() != 2) return "";
  // 1/6 and 3 as the model stores them (float16 in the selfie model: 1/6 -> 0.16663).
  const auto near = [](float value, float expected) { return std::abs(value - expected) < 1e-3f * expected; };
  const auto otherThan = [this, &near](const Node& binary, float constant) -> std::string {
    if (binary.inputs.size() != 2) return "";
    for (int i = 0; i < 2; ++i)
      if (near(scalar(binary.inputs[i]), constant)) return binary.inputs[1 - i];
    return "";
  };
  for (int i = 0; i < 2; ++i) {
    const Node* scaled = producer(n.inputs[i]);
    const Node* relu6 = producer(n.inputs[1 - i]);
    if (!scaled || !relu6 || scaled->op != "Mul" || relu6->op != "Relu6" || relu6->inputs.size() != 1) continue;
    const Node* shifted = producer(relu6->inputs[0]);
    if (!shifted || (shifted->op != "Add" && shifted->op != "AddV2")) continue;
    const std::string x = otherThan(*scaled, 1.f / 6.f);
    if (!x.empty() && x == otherThan(*shifted, 3.f)) return x;
  }
  return "";
}

void TfjsGraph::Impl::bypassNodes(const std::vector<std::string>& bypass, std::vector<Node>* out) const {
  for (const std::string& name : bypass)
    if (!index.count(name)) throw fileError(path, "bypassed node '" + name + "' is not a node");
  const std::set<std::string> bypassed(bypass.begin(), bypass.end());
  for (Node& n : *out)
    for (std::string& in : n.inputs)
      while (in[0] != '^' && bypassed.count(producerOf(in))) in = nodes[index.at(producerOf(in))].inputs.at(0);
}

void TfjsGraph::Impl::constantDilationPaddings(std::vector<Node>* out) const {
  std::vector<Node> zeros;
  for (Node& n : *out) {
    if (n.op != "BatchToSpaceND" || n.inputs.size() != 3) continue;
    const Node* conv = producer(n.inputs[0]);
    if (!conv || (conv->op != "DepthwiseConv2dNative" && conv->op != "Conv2D") || conv->inputs.empty()) continue;
    const Node* space = producer(conv->inputs[0]);
    if (!space || space->op != "SpaceToBatchND" || space->inputs.size() != 3) continue;
    // [[0, 0], [0, 0]] as int32, the paddings and the crops alike.
    zeros.push_back(Node{space->name + "/_zero_paddings", "Const", {},
                         {{"dtype", {{"type", "DT_INT32"}}}, {"value", Json::object()}},
                         Tensor{kInt32, {2, 2}, std::string(16, '\0')}});
    (*out)[index.at(space->name)].inputs[2] = zeros.back().name;
    n.inputs[2] = zeros.back().name;
  }
  out->insert(out->end(), zeros.begin(), zeros.end());
}

void TfjsGraph::Impl::scaledResizes(double factor, std::vector<Node>* out) const {
  if (!(factor > 0.0 && factor <= 4.0)) throw fileError(path, "resize_scale must be in (0, 4]");
  for (const Node& n : *out) {
    if ((n.op != "ResizeBilinear" && n.op != "ResizeNearestNeighbor") || n.inputs.size() != 2) continue;
    const auto size_index = index.find(producerOf(n.inputs[1]));
    if (size_index == index.end()) continue;
    Node& size = (*out)[size_index->second];
    const auto w = weights.find(size.name);
    if (size.op != "Const" || size.value || w == weights.end() || w->second.dtype != kInt32 ||
        w->second.data.size() != 8)
      continue;
    int32_t hw[2];
    std::memcpy(hw, w->second.data.data(), 8);
    for (int32_t& v : hw) v = std::max<int32_t>(1, static_cast<int32_t>(std::lround(v * factor)));
    size.value = Tensor{kInt32, w->second.shape, std::string(reinterpret_cast<const char*>(hw), 8)};
  }
}

void TfjsGraph::Impl::constantFirstSubtractions(std::vector<Node>* out) const {
  std::vector<Node> added;
  for (Node& n : *out) {
    if (n.op != "Sub" || n.inputs.size() != 2) continue;
    const Node* first = producer(n.inputs[0]);
    const Node* second = producer(n.inputs[1]);
    if (!first || first->op != "Const" || !second || second->op == "Const") continue;
    const float minus_one = -1.f;
    const Tensor t{kFloat, {}, std::string(reinterpret_cast<const char*>(&minus_one), 4)};
    const Json t_attr = {{"T", {{"type", "DT_FLOAT"}}}};
    added.push_back(Node{n.name + "/_minus_one", "Const", {},
                         {{"dtype", {{"type", "DT_FLOAT"}}}, {"value", Json::object()}}, t});
    added.push_back(Node{n.name + "/_negated", "Mul", {n.inputs[1], added.back().name}, t_attr, std::nullopt});
    n = Node{n.name, "AddV2", {added.back().name, n.inputs[0]}, t_attr, std::nullopt};
  }
  out->insert(out->end(), added.begin(), added.end());
}

std::vector<Node> TfjsGraph::Impl::rewritten(const Options& options,
                                             const std::map<std::string, int>& channel_scales) const {
  std::vector<Node> out = nodes;
  bypassNodes(options.bypass, &out);
  constantDilationPaddings(&out);
  constantFirstSubtractions(&out);
  if (options.resize_scale != 1.0) scaledResizes(options.resize_scale, &out);
  if (!options.fuse_layers) return out;
  for (Node& n : out) {
    const auto scale = channel_scales.find(n.name);
    if (scale != channel_scales.end()) {
      // OpenCV's Scale layer: input 0 the tensor, input 1 the per-channel factors.
      n = Node{n.name, "Scale", {n.inputs[1 - scale->second], n.inputs[scale->second]}, Json::object(), std::nullopt};
      continue;
    }
    const std::string x = hardSwishInput(n);
    if (!x.empty()) n = Node{n.name, "HardSwish", {x}, Json::object(), std::nullopt};
  }
  return out;
}

void TfjsGraph::Impl::readWeights(const Json& manifest, const std::string& dir) {
  for (const Json& group : manifest) {
    std::string buffer;
    for (const Json& shard : group.at("paths")) buffer += readBinary(dir + shard.get<std::string>());
    size_t offset = 0;
    for (const Json& w : group.at("weights")) {
      const std::string name = w.at("name").get<std::string>();
      const std::string dtype = w.at("dtype").get<std::string>();
      Tensor t;
      size_t count = 1;
      for (const Json& d : w.at("shape")) {
        t.shape.push_back(jsonInt(d));
        count *= static_cast<size_t>(t.shape.back());
      }
      std::string stored = dtype;
      float scale = 1, minimum = 0;
      if (w.contains("quantization")) {
        const Json& q = w["quantization"];
        stored = q.at("dtype").get<std::string>();
        if (stored == "uint8" || stored == "uint16") {
          scale = q.at("scale").get<float>();
          minimum = q.at("min").get<float>();
        }
      }
      const size_t bytes_per = stored == "float32" || stored == "int32" ? 4
                               : stored == "float16" || stored == "uint16" ? 2
                               : stored == "uint8" || stored == "bool"     ? 1
                                                                           : 0;
      if (bytes_per == 0) throw fileError(path, "weight '" + name + "' has unsupported type " + stored);
      if (offset + count * bytes_per > buffer.size())
        throw fileError(path, "weight shards end before weight '" + name + "'");
      const unsigned char* src = reinterpret_cast<const unsigned char*>(buffer.data()) + offset;
      offset += count * bytes_per;
      if (dtype == "float32") {
        std::vector<float> values(count);
        for (size_t i = 0; i < count; ++i) {
          if (stored == "float32") {
            std::memcpy(&values[i], src + 4 * i, 4);
          } else if (stored == "float16") {
            uint16_t h;
            std::memcpy(&h, src + 2 * i, 2);
            values[i] = halfToFloat(h);
          } else if (stored == "uint16") {
            uint16_t q;
            std::memcpy(&q, src + 2 * i, 2);
            values[i] = q * scale + minimum;
          } else {
            values[i] = src[i] * scale + minimum;
          }
        }
        t.dtype = kFloat;
        t.data.assign(reinterpret_cast<const char*>(values.data()), count * 4);
      } else if (dtype == "int32" && stored == "int32") {
        t.dtype = kInt32;
        t.data.assign(reinterpret_cast<const char*>(src), count * 4);
      } else if (dtype == "bool" && stored == "bool") {
        t.dtype = kBool;
        t.data.assign(reinterpret_cast<const char*>(src), count);
      } else {
        throw fileError(path, "weight '" + name + "': " + dtype + " stored as " + stored + " is not supported");
      }
      weights[name] = std::move(t);
    }
  }
}

void TfjsGraph::Impl::emitNode(ProtoWriter& graph, const Node& n) const {
  const bool fused_conv = n.op == "_FusedConv2D";
  const bool fused_depthwise = n.op == "FusedDepthwiseConv2dNative";
  if (!fused_conv && !fused_depthwise) {
    ProtoWriter node = nodeProto(n.name, n.op, n.inputs);
    for (const auto& [key, value] : n.attr.items()) {
      if (n.op == "Const" && key == "value" && n.value) {
        ProtoWriter tensor_value;
        tensor_value.message(8, tensorProto(*n.value));
        addAttr(node, key, tensor_value);
      } else if (n.op == "Const" && key == "value") {
        const auto w = weights.find(n.name);
        if (w == weights.end()) throw fileError(path, "constant '" + n.name + "' has no weights");
        ProtoWriter tensor_value;
        tensor_value.message(8, tensorProto(w->second));
        addAttr(node, key, tensor_value);
      } else if (key.rfind("_", 0) != 0) {  // "_grappler..." hints mean nothing to an importer
        addAttr(node, key, attrValue(key, value));
      }
    }
    graph.message(1, node);
    return;
  }
  // Fused convolution: conv(x, filter) -> BiasAdd(bias) -> optional activation. The last op keeps
  // the fused node's name, so its consumers need no change.
  std::vector<std::string> ops;
  if (n.attr.contains("fused_ops"))
    for (const Json& s : n.attr["fused_ops"]["list"]["s"]) ops.push_back(base64Decode(s.get<std::string>()));
  if (ops.empty() || ops[0] != "BiasAdd" || ops.size() > 2 || n.inputs.size() != 3)
    throw fileError(path, "fused node '" + n.name + "' is not conv + BiasAdd [+ activation]");
  static const std::set<std::string> kActivations = {"Relu", "Relu6", "Elu", "Sigmoid", "Tanh"};
  if (ops.size() == 2 && !kActivations.count(ops[1]))
    throw fileError(path, "fused node '" + n.name + "': activation " + ops[1] + " is not supported");

  const std::string conv_name = convNodeName(n.name);
  const std::string bias_name = ops.size() == 2 ? n.name + "/_bias" : n.name;
  ProtoWriter conv = nodeProto(conv_name, fused_conv ? "Conv2D" : "DepthwiseConv2dNative",
                               {n.inputs[0], n.inputs[1]});
  static const std::set<std::string> kConvAttrs = {"T", "strides", "padding", "explicit_paddings",
                                                   "data_format", "dilations"};
  for (const auto& [key, value] : n.attr.items())
    if (kConvAttrs.count(key)) addAttr(conv, key, attrValue(key, value));
  graph.message(1, conv);

  ProtoWriter bias = nodeProto(bias_name, "BiasAdd", {conv_name, n.inputs[2]});
  for (const char* key : {"T", "data_format"})
    if (n.attr.contains(key)) addAttr(bias, key, attrValue(key, n.attr[key]));
  graph.message(1, bias);

  if (ops.size() == 2) {
    ProtoWriter act = nodeProto(n.name, ops[1], {bias_name});
    if (n.attr.contains("T")) addAttr(act, "T", attrValue("T", n.attr["T"]));
    graph.message(1, act);
  }
}

TfjsGraph::TfjsGraph(const std::string& model_json_path) : impl_(std::make_unique<Impl>()) {
  impl_->path = model_json_path;
  std::ifstream in(model_json_path);
  if (!in) throw fileError(model_json_path, "cannot open TF.js model");
  Json model;
  try {
    model = Json::parse(in);
  } catch (const Json::exception& e) {
    throw fileError(model_json_path, std::string("not valid JSON: ") + e.what());
  }
  try {
    if (model.value("format", "") != "graph-model")
      throw fileError(model_json_path, "not a TF.js graph model (format is not \"graph-model\")");
    for (const Json& j : model.at("modelTopology").at("node")) {
      Node n;
      n.name = j.at("name").get<std::string>();
      n.op = j.at("op").get<std::string>();
      if (j.contains("input")) n.inputs = j["input"].get<std::vector<std::string>>();
      n.attr = j.value("attr", Json::object());
      if (!impl_->index.emplace(n.name, impl_->nodes.size()).second)
        throw fileError(model_json_path, "node '" + n.name + "' defined twice");
      impl_->nodes.push_back(std::move(n));
    }
    const size_t slash = model_json_path.rfind('/');
    const std::string dir = slash == std::string::npos ? "" : model_json_path.substr(0, slash + 1);
    impl_->readWeights(model.at("weightsManifest"), dir);
  } catch (const Json::exception& e) {
    throw fileError(model_json_path, std::string("unexpected model.json layout: ") + e.what());
  }
}

TfjsGraph::~TfjsGraph() = default;
TfjsGraph::TfjsGraph(TfjsGraph&&) noexcept = default;
TfjsGraph& TfjsGraph::operator=(TfjsGraph&&) noexcept = default;

bool TfjsGraph::hasNode(const std::string& name) const { return impl_->index.count(name) > 0; }

std::string TfjsGraph::layerName(const std::string& node) const {
  const auto it = impl_->index.find(node);
  if (it == impl_->index.end()) throw fileError(impl_->path, "no node '" + node + "'");
  const Node& n = impl_->nodes[it->second];
  const bool fused = n.op == "_FusedConv2D" || n.op == "FusedDepthwiseConv2dNative";
  if (fused && n.attr.contains("fused_ops") && n.attr["fused_ops"]["list"]["s"].size() == 1)
    return convNodeName(n.name);
  return n.name;
}

std::string TfjsGraph::toGraphDef(const Options& options) const { return impl_->graphDef(options, {}); }

std::string TfjsGraph::Impl::graphDef(const Options& options, const std::map<std::string, int>& channel_scales) const {
  for (const auto& [name, shape] : options.new_inputs)
    if (!index.count(name)) throw fileError(path, "new input '" + name + "' is not a node");
  const std::vector<Node> graph_nodes = rewritten(options, channel_scales);
  std::map<std::string, size_t> position_of;  // in graph_nodes, which may hold nodes a rewrite added
  for (size_t i = 0; i < graph_nodes.size(); ++i) position_of[graph_nodes[i].name] = i;

  // Nodes to keep: what the outputs need (by default the graph's own outputs, the nodes nothing
  // reads), walking inputs up to the new inputs; a fused chain's inner nodes fall away.
  std::vector<size_t> stack;
  for (const std::string& out : options.outputs) {
    const auto it = position_of.find(out);
    if (it == position_of.end()) throw fileError(path, "output '" + out + "' is not a node");
    stack.push_back(it->second);
  }
  if (options.outputs.empty()) {
    std::set<std::string> read;
    for (const Node& n : nodes)
      for (const std::string& in : n.inputs) read.insert(producerOf(in));
    for (size_t i = 0; i < nodes.size(); ++i)
      if (!read.count(nodes[i].name)) stack.push_back(i);
  }
  std::vector<bool> keep(graph_nodes.size(), false);
  while (!stack.empty()) {
    const size_t i = stack.back();
    stack.pop_back();
    if (keep[i]) continue;
    keep[i] = true;
    if (options.new_inputs.count(graph_nodes[i].name)) continue;
    for (const std::string& in : graph_nodes[i].inputs) {
      if (in[0] == '^') continue;  // control dependencies are dropped below: what only they reach is not needed either
      const auto it = position_of.find(producerOf(in));
      if (it == position_of.end())
        throw fileError(path, "node '" + graph_nodes[i].name + "' reads unknown node '" + in + "'");
      stack.push_back(it->second);
    }
  }

  ProtoWriter graph;
  for (size_t i = 0; i < graph_nodes.size(); ++i) {
    if (!keep[i]) continue;
    Node n = graph_nodes[i];
    const auto cut = options.new_inputs.find(n.name);
    if (cut != options.new_inputs.end()) {
      ProtoWriter node = nodeProto(n.name, "Placeholder", {});
      ProtoWriter type, shape_value, shape;
      type.varint(6, kFloat);
      addAttr(node, "dtype", type);
      writeShape(shape, std::vector<int64_t>(cut->second.begin(), cut->second.end()));
      shape_value.message(7, shape);
      addAttr(node, "shape", shape_value);
      graph.message(1, node);
      continue;
    }
    // Control dependencies order side effects TF.js graphs do not have; the importer needs none.
    std::vector<std::string> data_inputs;
    for (const std::string& in : n.inputs)
      if (in[0] != '^') data_inputs.push_back(in);
    n.inputs = data_inputs;
    emitNode(graph, n);
  }
  return graph.str();
}

cv::dnn::Net TfjsGraph::Impl::importNet(const std::string& graph_def) const {
  cv::dnn::Net net;
  try {
    net = cv::dnn::readNetFromTensorflow(graph_def.data(), graph_def.size());
  } catch (const cv::Exception& e) {
    throw fileError(path, std::string("OpenCV DNN cannot import the graph: ") + e.what());
  }
  if (net.empty()) throw fileError(path, "OpenCV DNN imported an empty network");
  net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  return net;
}

std::map<std::string, int> TfjsGraph::Impl::channelScales(cv::dnn::Net& net, const Options& options) const {
  // The network's one input, NHWC as the graph gives it: a new input's shape or a Placeholder's.
  std::vector<int> nhwc;
  if (options.new_inputs.size() == 1) nhwc = options.new_inputs.begin()->second;
  for (const Node& n : nodes) {
    if (!options.new_inputs.empty() || n.op != "Placeholder") continue;
    if (!nhwc.empty() || !n.attr.contains("shape")) return {};
    for (const Json& d : n.attr["shape"]["shape"].value("dim", Json::array()))
      nhwc.push_back(d.contains("size") ? static_cast<int>(jsonInt(d["size"])) : -1);
  }
  if (nhwc.size() != 4 || *std::min_element(nhwc.begin(), nhwc.end()) <= 0) return {};
  std::vector<int> ids;
  std::vector<std::vector<cv::dnn::MatShape>> in_shapes, out_shapes;
  try {
    net.getLayersShapes(cv::dnn::MatShape{nhwc[0], nhwc[3], nhwc[1], nhwc[2]}, ids, in_shapes, out_shapes);
  } catch (const cv::Exception&) {
    return {};  // the fusion is an optimisation: a net OpenCV cannot size runs as imported
  }
  const auto isChannelVector = [](const cv::dnn::MatShape& v, const cv::dnn::MatShape& t) {
    return v.size() == 4 && t.size() == 4 && v[0] == t[0] && v[1] == t[1] && v[2] == 1 && v[3] == 1 &&
           t[2] * t[3] > 1;
  };
  std::map<std::string, int> scales;
  for (size_t i = 0; i < ids.size(); ++i) {
    const cv::Ptr<cv::dnn::Layer> layer = net.getLayer(ids[i]);
    const Node* n = producer(layer->name);
    if (layer->type != "Eltwise" || !n || n->op != "Mul" || n->inputs.size() != 2 || in_shapes[i].size() != 2)
      continue;
    for (int v = 0; v < 2; ++v)
      if (isChannelVector(in_shapes[i][v], in_shapes[i][1 - v])) scales[n->name] = v;
  }
  return scales;
}

cv::dnn::Net TfjsGraph::loadNet(const Options& options) const {
  cv::dnn::Net net = impl_->importNet(impl_->graphDef(options, {}));
  if (!options.fuse_layers) return net;
  const std::map<std::string, int> scales = impl_->channelScales(net, options);
  return scales.empty() ? net : impl_->importNet(impl_->graphDef(options, scales));
}

cv::Mat TfjsGraph::constant(const std::string& name) const {
  const auto it = impl_->weights.find(name);
  if (it == impl_->weights.end()) throw fileError(impl_->path, "no constant '" + name + "'");
  const Tensor& t = it->second;
  const int bytes_per = t.dtype == kBool ? 1 : 4;
  const int count = static_cast<int>(t.data.size() / bytes_per);
  cv::Mat values(1, count, CV_32F);
  for (int i = 0; i < count; ++i) {
    const char* p = t.data.data() + static_cast<size_t>(i) * bytes_per;
    if (t.dtype == kFloat) {
      std::memcpy(&values.at<float>(i), p, 4);
    } else if (t.dtype == kInt32) {
      int32_t v;
      std::memcpy(&v, p, 4);
      values.at<float>(i) = static_cast<float>(v);
    } else {
      values.at<float>(i) = *p ? 1.f : 0.f;
    }
  }
  return values;
}

}  // namespace pf2
