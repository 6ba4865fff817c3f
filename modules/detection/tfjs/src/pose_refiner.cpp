#include "pf2/detection/pose_refiner.h"

#include <algorithm>
#include <cmath>

#include "pf2/core/error.h"
#include "pf2/detection/movenet_detector.h"

namespace pf2 {
namespace {

float overlap(const PersonBox& a, const PersonBox& b) {
  const float w = std::min(a.x_lr, b.x_lr) - std::max(a.x_ul, b.x_ul);
  const float h = std::min(a.y_lr, b.y_lr) - std::max(a.y_ul, b.y_ul);
  if (w <= 0 || h <= 0) return 0.f;
  const float inter = w * h;
  return inter / (a.width() * a.height() + b.width() * b.height() - inter);
}

}  // namespace

cv::Mat cropWithBlackBorder(const cv::Mat& bgr, const cv::Rect& crop) {
  cv::Mat out(crop.size(), CV_8UC3, cv::Scalar::all(0));
  const cv::Rect inside = crop & cv::Rect(0, 0, bgr.cols, bgr.rows);
  if (!inside.empty()) bgr(inside).copyTo(out(inside - crop.tl()));
  return out;
}

cv::Rect refinementCropPixels(const PersonBox& box, double margin) {
  const cv::Rect2f area = refinementCrop(box, margin);
  return {cvRound(area.x), cvRound(area.y), std::max(1, cvRound(area.width)), std::max(1, cvRound(area.height))};
}

cv::Rect2f refinementCrop(const PersonBox& box, double margin) {
  const float side = static_cast<float>((1.0 + margin) * std::max(box.width(), box.height()));
  const float cx = 0.5f * (box.x_ul + box.x_lr), cy = 0.5f * (box.y_ul + box.y_lr);
  return {cx - side / 2, cy - side / 2, side, side};
}

PoseRefiner::PoseRefiner(const Options& options) : options_(options) {
  if (options_.input_size < 64 || options_.input_size > 512 || options_.input_size % 32 != 0)
    throw Error("pose refiner: input_size must be a multiple of 32 in [64, 512]");
  if (!(options_.margin >= 0 && options_.margin <= 2)) throw Error("pose refiner: margin must be in [0, 2]");
  if (!(options_.min_iou >= 0 && options_.min_iou <= 1)) throw Error("pose refiner: min_iou must be in [0, 1]");
  MoveNetDetector::Options movenet;
  movenet.input_width = movenet.input_height = options_.input_size;
  movenet_ = std::make_unique<MoveNetDetector>(movenet);
}

PoseRefiner::~PoseRefiner() = default;

bool PoseRefiner::refine(const cv::Mat& bgr, const PersonBox& box, std::vector<Keypoint2d>* keypoints) {
  PersonDetection person;
  if (!find(bgr, box, &person)) return false;
  *keypoints = std::move(person.keypoints);
  return true;
}

bool PoseRefiner::find(const cv::Mat& bgr, const PersonBox& box, PersonDetection* person) {
  if (bgr.empty() || bgr.type() != CV_8UC3) throw Error("pose refiner: expected a non-empty 8-bit BGR image");
  if (box.empty()) return false;
  const cv::Rect crop = refinementCropPixels(box, options_.margin);
  Frame view;
  view.rgb = cropWithBlackBorder(bgr, crop);
  const Detections found = movenet_->detect(view);
  const PersonBox expected{box.x_ul - crop.x, box.y_ul - crop.y, box.x_lr - crop.x, box.y_lr - crop.y};
  const PersonDetection* best = nullptr;
  float best_iou = static_cast<float>(options_.min_iou);
  for (const PersonDetection& candidate : found.people) {
    const float o = overlap(candidate.box, expected);
    if (o >= best_iou && !candidate.keypoints.empty()) best = &candidate, best_iou = o;
  }
  if (best == nullptr) return false;
  *person = *best;
  const float du = static_cast<float>(crop.x), dv = static_cast<float>(crop.y);
  person->box = {best->box.x_ul + du, best->box.y_ul + dv, best->box.x_lr + du, best->box.y_lr + dv};
  for (Keypoint2d& k : person->keypoints) k.u += du, k.v += dv;
  return true;
}

}  // namespace pf2
