#include "pf2/detection/crop_segmenter.h"

#include <opencv2/dnn.hpp>
#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"
#include "pf2/detection/learned_models.h"
#include "pf2/detection/pose_refiner.h"
#include "pf2/detection/tfjs_graph.h"

namespace pf2 {
namespace {
constexpr int kExportedSize = 256;  // the input side the model was exported for (its upsamplings' sizes)
// The segmentation head's output (after its sigmoid); cutting the graph there drops the landmark
// and pose-presence heads, which are not used.
constexpr const char* kSegmentationNode = "StatefulPartitionedCall/model/activation_segmentation/Sigmoid";
}  // namespace

struct PersonCropSegmenter::Impl {
  cv::dnn::Net net;
  std::string output_layer;
};

PersonCropSegmenter::PersonCropSegmenter(const Options& options)
    : options_(options), impl_(std::make_unique<Impl>()) {
  if (!(options_.margin >= 0.0 && options_.margin <= 2.0)) throw Error("crop segmenter: margin must be in [0, 2]");
  if (!(options_.mask_threshold > 0.f && options_.mask_threshold < 1.f))
    throw Error("crop segmenter: mask_threshold must be in (0, 1)");
  if (options_.input_size != 192 && options_.input_size != 224 && options_.input_size != 256)
    throw Error("crop segmenter: input_size must be 192, 224 or 256");
  if (options_.model_json.empty()) options_.model_json = humanModelPath("blazepose-lite");
  const TfjsGraph graph(options_.model_json);
  TfjsGraph::Options cut;
  cut.outputs = {kSegmentationNode};
  cut.resize_scale = static_cast<double>(options_.input_size) / kExportedSize;
  impl_->net = graph.loadNet(cut);
  impl_->output_layer = graph.layerName(kSegmentationNode);
}

PersonCropSegmenter::~PersonCropSegmenter() = default;

cv::Mat PersonCropSegmenter::segment(const cv::Mat& bgr, const PersonBox& box) {
  if (bgr.empty() || bgr.type() != CV_8UC3) throw Error("crop segmenter: expected a non-empty 8-bit BGR image");
  cv::Mat mask(bgr.size(), CV_8U, cv::Scalar(0));
  if (box.empty()) return mask;
  const cv::Rect crop = refinementCropPixels(box, options_.margin);
  const cv::Rect inside = crop & cv::Rect(0, 0, bgr.cols, bgr.rows);
  if (inside.empty()) return mask;
  // The model takes RGB in [0, 1].
  const int side = options_.input_size;
  impl_->net.setInput(cv::dnn::blobFromImage(cropWithBlackBorder(bgr, crop), 1.0 / 255.0,
                                             cv::Size(side, side), cv::Scalar(), true, false));
  const cv::Mat out = impl_->net.forward(impl_->output_layer);
  if (out.total() != static_cast<size_t>(side * side))
    throw Error("crop segmenter: unexpected network output size");
  const cv::Mat small(side, side, CV_32F, const_cast<float*>(out.ptr<float>()));
  cv::Mat probability;
  cv::resize(small, probability, crop.size(), 0, 0, cv::INTER_LINEAR);
  mask(inside).setTo(255, probability(inside - crop.tl()) > options_.mask_threshold);
  return mask;
}

}  // namespace pf2
