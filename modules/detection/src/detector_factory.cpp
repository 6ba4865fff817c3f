#include "pf2/detection/detector_factory.h"

#include <functional>
#include <map>

#include "pf2/core/error.h"

#include "pf2/detection/tfjs_factory.h"

namespace pf2 {
namespace {

using Factory = std::function<std::unique_ptr<HumanDetector>(const DetectorOptions&)>;

const std::map<std::string, Factory>& registry() {
  static const std::map<std::string, Factory> factories = {
      {"gt", [](const DetectorOptions& o) { return std::make_unique<GtDetector>(o.gt); }},
      {"hog", [](const DetectorOptions& o) { return std::make_unique<HogDetector>(o.hog); }},
      {"file", [](const DetectorOptions& o) { return std::make_unique<FileDetector>(o.file); }},
      {"yolo", [](const DetectorOptions& o) { return std::make_unique<YoloDetector>(o.yolo); }},
      // Learned (TF.js) backends (modules/detection/tfjs); their options come from
      // DetectorOptions::extra ("key" -> "value").
      {"selfie", [](const DetectorOptions& o) { return createSelfieDetector(o.extra); }},
      {"movenet", [](const DetectorOptions& o) { return createMoveNetDetector(o.extra); }},
      {"learned", [](const DetectorOptions& o) { return createLearnedDetector(o.extra); }},
  };
  return factories;
}

}  // namespace

std::unique_ptr<HumanDetector> createHumanDetector(const std::string& name, const DetectorOptions& options) {
  const auto& factories = registry();
  const auto found = factories.find(name);
  if (found == factories.end()) {
    std::string known;
    for (const auto& entry : factories) known += (known.empty() ? "" : ", ") + entry.first;
    throw Error("unknown detector '" + name + "' (this build knows: " + known + ")");
  }
  return found->second(options);
}

std::vector<std::string> humanDetectorNames() {
  std::vector<std::string> names;
  for (const auto& entry : registry()) names.push_back(entry.first);
  return names;
}

}  // namespace pf2
