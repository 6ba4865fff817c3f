#include "pf2/detection/movenet_detector.h"

#include <algorithm>
#include <cmath>

#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"
#include "pf2/detection/learned_models.h"
#include "pf2/detection/tfjs_graph.h"

namespace pf2 {
namespace {

constexpr int kKeypoints = 17;
constexpr int kStride = 4;  // output grid cell in input pixels
const std::string kPrefix = "StatefulPartitionedCall/";
// Where the graph is cut: its normalised float input, and its six heads (NHWC in the graph).
const std::string kNormalised = kPrefix + "sub_1";
const std::string kCentre = kPrefix + "Sigmoid";                             // 1: person centre
const std::string kHeatmap = kPrefix + "Sigmoid_1";                          // 17: keypoint heatmaps
const std::string kRegress = kPrefix + "kpt_regress_0/conv2d_8/BiasAdd";     // 34: centre -> keypoint (dy, dx)
const std::string kOffset = kPrefix + "kpt_offset_0/conv2d_9/BiasAdd";       // 34: sub-cell (dy, dx)
const std::string kBoxScale = kPrefix + "box_scale_0/conv2d_5/BiasAdd";      // 2: box (h, w)
const std::string kBoxOffset = kPrefix + "box_offset_0/conv2d_6/BiasAdd";    // 2: box centre (dy, dx)
// The graph's decoding constants: centre peaks are 5x5 maxima; a keypoint candidate is weighted
// by exp(-d^2 / (kSpread * min(grid h, grid w))), d its distance in cells to the regressed point.
constexpr int kPeakWindow = 5;
constexpr float kSpread = 0.3f;

// Channel c of an NCHW blob (batch 1) as an h x w matrix header.
cv::Mat channel(const cv::Mat& blob, int c) {
  return cv::Mat(blob.size[2], blob.size[3], CV_32F, const_cast<float*>(blob.ptr<float>(0, c)));
}

}  // namespace

std::vector<PersonDetection> decodeMoveNet(const std::vector<cv::Mat>& heads, float cell_u, float cell_v,
                                          const MoveNetDetector::Options& options) {
  if (heads.size() != 6) throw Error("movenet: expected 6 heads");
  const int expected_channels[] = {1, kKeypoints, 2 * kKeypoints, 2 * kKeypoints, 2, 2};
  for (size_t i = 0; i < heads.size(); ++i)
    if (heads[i].dims != 4 || heads[i].size[1] != expected_channels[i] || heads[i].size[2] != heads[0].size[2] ||
        heads[i].size[3] != heads[0].size[3])
      throw Error("movenet: head " + std::to_string(i) + " has an unexpected shape");
  std::vector<PersonDetection> people;
  const cv::Mat &heat = heads[1], &regress = heads[2], &offset = heads[3], &box_scale = heads[4],
                &box_offset = heads[5];
  const cv::Mat centre = channel(heads[0], 0);
  const int gh = centre.rows, gw = centre.cols;

  // Person centres: 5x5 local maxima of the centre heatmap, best first.
  cv::Mat local_max;
  cv::dilate(centre, local_max, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(kPeakWindow, kPeakWindow)));
  std::vector<std::pair<float, cv::Point>> peaks;
  for (int y = 0; y < gh; ++y)
    for (int x = 0; x < gw; ++x)
      if (centre.at<float>(y, x) >= local_max.at<float>(y, x)) peaks.push_back({centre.at<float>(y, x), {x, y}});
  std::sort(peaks.begin(), peaks.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  if (static_cast<int>(peaks.size()) > options.max_people) peaks.resize(options.max_people);

  const float spread = kSpread * std::min(gh, gw);
  for (const auto& [centre_score, c] : peaks) {
    // Box in grid cells, clipped to the grid.
    const float h = std::max(0.f, channel(box_scale, 0).at<float>(c)), w = std::max(0.f, channel(box_scale, 1).at<float>(c));
    const float yc = c.y + channel(box_offset, 0).at<float>(c), xc = c.x + channel(box_offset, 1).at<float>(c);
    const float y0 = std::clamp(yc - h / 2, 0.f, static_cast<float>(gh)), y1 = std::clamp(yc + h / 2, 0.f, static_cast<float>(gh));
    const float x0 = std::clamp(xc - w / 2, 0.f, static_cast<float>(gw)), x1 = std::clamp(xc + w / 2, 0.f, static_cast<float>(gw));

    PersonDetection person;
    person.keypoints.resize(kKeypoints);
    float score_sum = 0;
    int confident = 0;
    for (int k = 0; k < kKeypoints; ++k) {
      const float ry = c.y + channel(regress, 2 * k).at<float>(c), rx = c.x + channel(regress, 2 * k + 1).at<float>(c);
      const cv::Mat hk = channel(heat, k);
      float best = -1;
      cv::Point at;
      for (int y = static_cast<int>(std::ceil(y0)); y < y1; ++y)
        for (int x = static_cast<int>(std::ceil(x0)); x < x1; ++x) {
          const float d2 = (y - ry) * (y - ry) + (x - rx) * (x - rx);
          const float v = hk.at<float>(y, x) * std::exp(-d2 / spread);
          if (v > best) {
            best = v;
            at = {x, y};
          }
        }
      Keypoint2d& kp = person.keypoints[k];
      if (best < 0) {  // empty box: fall back on the regressed point, unscored
        kp = {rx * cell_u, ry * cell_v, 0.f};
        continue;
      }
      kp.u = (at.x + channel(offset, 2 * k + 1).at<float>(at)) * cell_u;
      kp.v = (at.y + channel(offset, 2 * k).at<float>(at)) * cell_v;
      kp.score = best;
      if (best > options.keypoint_threshold) {
        score_sum += best;
        ++confident;
      }
    }
    // As the graph scores an instance: centre confidence times the mean confident keypoint score.
    person.score = confident > 0 ? centre_score * score_sum / confident : 0.f;
    if (person.score < options.min_person_score) continue;
    person.box = {x0 * cell_u, y0 * cell_v, x1 * cell_u, y1 * cell_v};
    people.push_back(std::move(person));
  }
  return people;
}

struct MoveNetDetector::Impl {
  cv::dnn::Net net;
  std::vector<std::string> layers;  // OpenCV layer names of the six heads, order as below
  cv::Scalar mean, scale;           // the graph's normalisation (x - mean) * scale - offset
  float offset = 0;
};

MoveNetDetector::MoveNetDetector(const Options& options) : options_(options), impl_(std::make_unique<Impl>()) {
  if (options_.input_width <= 0 || options_.input_height <= 0 || options_.input_width % 32 != 0 ||
      options_.input_height % 32 != 0)
    throw Error("movenet: input size must be positive multiples of 32");
  if (options_.model_json.empty()) options_.model_json = humanModelPath("movenet-multipose");
  const TfjsGraph graph(options_.model_json);
  TfjsGraph::Options cut;
  cut.new_inputs[kNormalised] = {1, options_.input_height, options_.input_width, 3};
  cut.outputs = {kCentre, kHeatmap, kRegress, kOffset, kBoxScale, kBoxOffset};
  impl_->net = graph.loadNet(cut);
  for (const std::string& node : cut.outputs) impl_->layers.push_back(graph.layerName(node));
  // The cut-off pre-processing: sub_1 = (cast(input) - Reshape) * truediv - sub_1/y, per RGB channel.
  const cv::Mat mean = graph.constant(kPrefix + "Reshape"), scale = graph.constant(kPrefix + "truediv");
  if (mean.total() != 3 || scale.total() != 3)
    throw fileError(options_.model_json, "unexpected normalisation constants");
  impl_->mean = cv::Scalar(mean.at<float>(0), mean.at<float>(1), mean.at<float>(2));
  impl_->scale = cv::Scalar(scale.at<float>(0), scale.at<float>(1), scale.at<float>(2));
  impl_->offset = graph.constant(kPrefix + "sub_1/y").at<float>(0);
}

MoveNetDetector::~MoveNetDetector() = default;

Detections MoveNetDetector::detect(const Frame& frame) {
  if (frame.rgb.empty() || frame.rgb.type() != CV_8UC3)
    throw Error("movenet: expected a non-empty 8-bit BGR image");
  Detections result;
  result.timestamp = frame.timestamp;

  cv::Mat rgb;
  cv::resize(frame.rgb, rgb, cv::Size(options_.input_width, options_.input_height), 0, 0, cv::INTER_LINEAR);
  cv::cvtColor(rgb, rgb, cv::COLOR_BGR2RGB);
  rgb.convertTo(rgb, CV_32FC3);
  cv::Mat normalised;
  cv::multiply(rgb - impl_->mean, impl_->scale, normalised);
  normalised -= cv::Scalar::all(impl_->offset);
  impl_->net.setInput(cv::dnn::blobFromImage(normalised));
  std::vector<cv::Mat> heads;
  impl_->net.forward(heads, impl_->layers);
  const float cell_u = static_cast<float>(frame.rgb.cols) / options_.input_width * kStride;
  const float cell_v = static_cast<float>(frame.rgb.rows) / options_.input_height * kStride;
  result.people = decodeMoveNet(heads, cell_u, cell_v, options_);
  return result;
}

}  // namespace pf2
