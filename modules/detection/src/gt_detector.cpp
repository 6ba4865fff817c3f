#include "pf2/detection/gt_detector.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "nearest_stamp.h"
#include "pf2/core/text_lines.h"
#include "pf2/core/error.h"

namespace pf2 {

GtDetector::GtDetector(const Options& options) : options_(options) {
  const std::string path = options.gt_folder + "/boxes.txt";
  forEachDataLine(path, "ground-truth boxes (is this a pf2_synth sequence?)", [&](const std::string& line,
                                                                                  int number) {
    std::istringstream fields(line);
    double stamp = 0, visible = 0;
    Entry e;
    if (!(fields >> stamp >> e.id >> e.box.x_ul >> e.box.y_ul >> e.box.x_lr >> e.box.y_lr >> visible)) {
      throw fileError(path, number, "expected 'timestamp id x_ul y_ul x_lr y_lr visible_fraction'");
    }
    if (!std::isfinite(stamp) || !std::isfinite(e.box.x_ul) || !std::isfinite(e.box.y_ul) ||
        !std::isfinite(e.box.x_lr) || !std::isfinite(e.box.y_lr) || !std::isfinite(visible)) {
      throw fileError(path, number, "non-finite number");
    }
    if (e.box.x_lr < e.box.x_ul || e.box.y_lr < e.box.y_ul) {
      throw fileError(path, number, "box corners out of order (x_lr < x_ul or y_lr < y_ul)");
    }
    // pf2_synth's corners are inclusive (the last pixel of the mask); PersonBox's lower right is
    // exclusive like cv::Rect.
    e.box.x_lr += 1;
    e.box.y_lr += 1;
    e.visible_fraction = visible;
    boxes_[stamp].push_back(e);
  });
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
  const std::vector<Entry>* entries = nearestStamp(boxes_, frame.timestamp, options_.max_time_difference);
  cv::Mat ids;
  if (entries && options_.provide_mask) {
    const std::string* file = nearestStamp(mask_files_, frame.timestamp, options_.max_time_difference);
    if (!file) {
      throw Error(options_.gt_folder + "/masks: no mask for frame " + std::to_string(frame.timestamp));
    }
    ids = cv::imread(*file, cv::IMREAD_UNCHANGED);
    if (ids.empty()) throw fileError(*file, "cannot read mask image");
    if ((ids.type() != CV_16U && ids.type() != CV_8U) || (!frame.depth.empty() && ids.size() != frame.depth.size())) {
      throw fileError(*file, "mask must be a single-channel 8/16-bit image of the frame's size");
    }
  }
  if (entries) {
    for (const Entry& e : *entries) {
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
