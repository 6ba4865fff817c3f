#include "pf2/detection/gt_detector.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "nearest_stamp.h"
#include "pf2/core/text_lines.h"
#include "pf2/core/error.h"
#include "pf2/io/image_file.h"

namespace pf2 {

std::vector<GroundTruthBox> readGroundTruthBoxes(const std::string& path) {
  std::vector<GroundTruthBox> boxes;
  forEachDataLine(path, "ground-truth boxes (is this a pf2_synth sequence?)", [&](const std::string& line,
                                                                                  int number) {
    std::istringstream fields(line);
    GroundTruthBox e;
    PersonBox& b = e.box;
    if (!(fields >> e.timestamp >> e.id >> b.x_ul >> b.y_ul >> b.x_lr >> b.y_lr >> e.visible_fraction)) {
      throw fileError(path, number, "expected 'timestamp id x_ul y_ul x_lr y_lr visible_fraction'");
    }
    if (!std::isfinite(e.timestamp) || !std::isfinite(b.x_ul) || !std::isfinite(b.y_ul) ||
        !std::isfinite(b.x_lr) || !std::isfinite(b.y_lr) || !std::isfinite(e.visible_fraction)) {
      throw fileError(path, number, "non-finite number");
    }
    if (b.x_lr < b.x_ul || b.y_lr < b.y_ul) {
      throw fileError(path, number, "box corners out of order (x_lr < x_ul or y_lr < y_ul)");
    }
    // pf2_synth's corners are inclusive (the last pixel of the mask); PersonBox's lower right is
    // exclusive like cv::Rect.
    b.x_lr += 1;
    b.y_lr += 1;
    boxes.push_back(e);
  });
  return boxes;
}

GtDetector::GtDetector(const Options& options) : options_(options) {
  for (const GroundTruthBox& b : readGroundTruthBoxes(options.gt_folder + "/boxes.txt")) {
    boxes_[b.timestamp].push_back(b);
  }
  if (options.provide_mask) {
    const std::string masks = options.gt_folder + "/masks";
    std::error_code error;
    for (const auto& file : std::filesystem::directory_iterator(masks, error)) {
      if (file.path().extension() != ".png") continue;
      const std::string stem = file.path().stem().string();
      char* end = nullptr;
      const double stamp = std::strtod(stem.c_str(), &end);
      if (end == stem.c_str() || *end != '\0') continue;  // not a "<stamp>.png"
      mask_files_[stamp] = file.path().string();
    }
    if (error) throw fileError(masks, "cannot list mask folder: " + error.message());
  }
}

Detections GtDetector::detect(const Frame& frame) {
  Detections detections;
  detections.timestamp = frame.timestamp;
  const std::vector<GroundTruthBox>* entries = nearestStamp(boxes_, frame.timestamp, options_.max_time_difference);
  cv::Mat ids;
  if (entries && options_.provide_mask) {
    const std::string* file = nearestStamp(mask_files_, frame.timestamp, options_.max_time_difference);
    if (!file) {
      throw Error(options_.gt_folder + "/masks: no mask for frame " + std::to_string(frame.timestamp));
    }
    ids = readImageFile(*file, cv::IMREAD_UNCHANGED, "ground-truth mask", frame.depth.size());
    if ((ids.type() != CV_16U && ids.type() != CV_8U) || (!frame.depth.empty() && ids.size() != frame.depth.size())) {
      throw fileError(*file, "mask must be a single-channel 8/16-bit image of the frame's size");
    }
  }
  if (entries) {
    for (const GroundTruthBox& e : *entries) {
      if (e.visible_fraction < options_.min_visible_fraction) continue;
      PersonDetection person;
      person.box = e.box;
      person.score = 1.0f;
      if (!ids.empty()) person.mask = ids == static_cast<double>(e.id);
      detections.people.push_back(std::move(person));
    }
  }
  const cv::Size size = !frame.rgb.empty() ? frame.rgb.size()
                        : !frame.depth.empty() ? frame.depth.size()
                                               : cv::Size(frame.intrinsics.width, frame.intrinsics.height);
  degradeDetections(options_.degradation, size, &detections);
  return detections;
}

}  // namespace pf2
