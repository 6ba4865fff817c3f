#pragma once
// Builders the detector factory (modules/detection/src/detector_factory.cpp) calls for the learned
// backends. Options come as "key" -> "value" text (DetectorOptions::extra); keys, all optional:
//   model             for "selfie" and "movenet": the same as selfie.model / movenet.model
//                     (an error for "learned", which has two models)
//   selfie.model      path of selfie's model.json (default: humanModelPath("selfie"))
//   selfie.threshold  mask probability threshold (0.5)
//   selfie.min_area   smallest component, fraction of the image (0.01)
//   selfie.square_crops  1: two square crops per frame instead of one stretched frame (0)
//   selfie.min_score  smallest mean probability of a kept component (0.7)
//   movenet.model     path of MoveNet MultiPose's model.json (default: humanModelPath("movenet-multipose"))
//   movenet.width, movenet.height   network input in pixels, multiples of 32 (256, 192)
//   movenet.min_score smallest person score kept (0.2)
//   learned.pose_every  frames per MoveNet run in "learned" (3)
//   learned.min_keypoints  confident keypoints (score >= 0.3) a pose needs to be a person (4)
//   learned.max_component  mask components above this fraction of the image are cut to the
//                     people's boxes (0.6)
//   learned.segmenter  selfie | rvm: where the person probability comes from (selfie)
// Keys of other prefixes are ignored (they belong to other backends); an unknown key with one of
// these prefixes or a value that does not parse throws pf2::Error naming the key.
#include <map>
#include <memory>
#include <string>

#include "pf2/detection/human_detector.h"

namespace pf2 {

using DetectorExtraOptions = std::map<std::string, std::string>;

std::unique_ptr<HumanDetector> createSelfieDetector(const DetectorExtraOptions& extra);
std::unique_ptr<HumanDetector> createMoveNetDetector(const DetectorExtraOptions& extra);
std::unique_ptr<HumanDetector> createLearnedDetector(const DetectorExtraOptions& extra);

}  // namespace pf2
