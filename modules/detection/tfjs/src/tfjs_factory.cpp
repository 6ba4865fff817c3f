#include "pf2/detection/tfjs_factory.h"

#include <set>

#include "pf2/core/error.h"
#include "pf2/detection/learned_person_detector.h"
#include "pf2/detection/movenet_detector.h"
#include "pf2/detection/selfie_segmenter.h"

namespace pf2 {
namespace {

// Reads the keys of the "selfie.", "movenet." and "learned." families, rejecting misspelt ones.
class ExtraReader {
 public:
  explicit ExtraReader(const DetectorExtraOptions& extra) : extra_(extra) {
    static const std::set<std::string> kKnown = {
        "selfie.model",    "selfie.threshold", "selfie.min_area",   "selfie.square_crops", "selfie.min_score", "movenet.model",
        "movenet.width",   "movenet.height",   "movenet.min_score", "learned.pose_every",
        "learned.min_keypoints", "learned.max_component", "learned.segmenter", "learned.crop_masks",
        "learned.crop_size", "learned.candidate_poses"};
    for (const auto& entry : extra_) {
      const std::string family = entry.first.substr(0, entry.first.find('.') + 1);
      if ((family == "selfie." || family == "movenet." || family == "learned.") && !kKnown.count(entry.first))
        throw Error("unknown detector option '" + entry.first + "'");
    }
  }
  void text(const std::string& key, std::string* value) const {
    const auto it = extra_.find(key);
    if (it != extra_.end()) *value = it->second;
  }
  template <typename T>
  void number(const std::string& key, T* value) const {
    const auto it = extra_.find(key);
    if (it == extra_.end()) return;
    size_t used = 0;
    double parsed = 0;
    try {
      parsed = std::stod(it->second, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != it->second.size())
      throw Error("detector option '" + key + "': '" + it->second + "' is not a number");
    *value = static_cast<T>(parsed);
  }
  // A switch: 0 or 1 (a number would silently turn any other value into "on").
  void flag(const std::string& key, bool* value) const {
    double parsed = *value ? 1 : 0;
    number(key, &parsed);
    if (parsed != 0 && parsed != 1)
      throw Error("detector option '" + key + "': expected 0 or 1, got '" + extra_.at(key) + "'");
    *value = parsed == 1;
  }

 private:
  const DetectorExtraOptions& extra_;
};

SelfieSegmenter::Options selfieOptions(const ExtraReader& r) {
  SelfieSegmenter::Options o;
  r.text("selfie.model", &o.model_json);
  r.number("selfie.threshold", &o.mask_threshold);
  r.number("selfie.min_area", &o.min_area_fraction);
  r.flag("selfie.square_crops", &o.square_crops);
  r.number("selfie.min_score", &o.min_score);
  return o;
}

MoveNetDetector::Options moveNetOptions(const ExtraReader& r) {
  MoveNetDetector::Options o;
  r.text("movenet.model", &o.model_json);
  r.number("movenet.width", &o.input_width);
  r.number("movenet.height", &o.input_height);
  r.number("movenet.min_score", &o.min_person_score);
  return o;
}

}  // namespace

std::unique_ptr<HumanDetector> createSelfieDetector(const DetectorExtraOptions& extra) {
  const ExtraReader r(extra);
  SelfieSegmenter::Options o = selfieOptions(r);
  r.text("model", &o.model_json);
  return std::make_unique<SelfieSegmenter>(o);
}

std::unique_ptr<HumanDetector> createMoveNetDetector(const DetectorExtraOptions& extra) {
  const ExtraReader r(extra);
  MoveNetDetector::Options o = moveNetOptions(r);
  r.text("model", &o.model_json);
  return std::make_unique<MoveNetDetector>(o);
}

std::unique_ptr<HumanDetector> createLearnedDetector(const DetectorExtraOptions& extra) {
  if (extra.count("model"))
    throw Error("detector 'learned' uses two models: give selfie.model and movenet.model, not model");
  const ExtraReader r(extra);
  LearnedPersonDetector::Options o;
  o.selfie = selfieOptions(r);
  o.movenet = moveNetOptions(r);
  r.number("learned.pose_every", &o.pose_every);
  r.number("learned.min_keypoints", &o.min_pose_keypoints);
  r.number("learned.max_component", &o.max_component_fraction);
  r.text("learned.segmenter", &o.segmenter);
  r.flag("learned.crop_masks", &o.crop_masks);
  r.number("learned.crop_size", &o.crop.input_size);
  r.flag("learned.candidate_poses", &o.candidate_poses);
  return std::make_unique<LearnedPersonDetector>(o);
}

}  // namespace pf2
