#pragma once
// Detectors are chosen by name (DESIGN.md: variants of a stage behind one interface, picked in the
// options, never by if-chains in the pipeline). The registry lives in src/detector_factory.cpp.
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pf2/detection/file_detector.h"
#include "pf2/detection/gt_detector.h"
#include "pf2/detection/hog_detector.h"
#include "pf2/detection/human_detector.h"
#include "pf2/detection/yolo_detector.h"

namespace pf2 {

struct DetectorOptions {
  GtDetector::Options gt;
  HogDetector::Options hog;
  FileDetector::Options file;
  YoloDetector::Options yolo;
  // "key" -> "value" for backends registered from other libraries (the TF.js ones: e.g.
  // "model" -> path); each such backend documents its keys.
  std::map<std::string, std::string> extra;
};

// Creates the backend called `name`. Throws pf2::Error listing the known names for an unknown one,
// and whatever the backend's constructor throws (missing files...). Thread safe.
std::unique_ptr<HumanDetector> createHumanDetector(const std::string& name, const DetectorOptions& options);
// The names createHumanDetector accepts in this build, sorted.
std::vector<std::string> humanDetectorNames();

}  // namespace pf2
