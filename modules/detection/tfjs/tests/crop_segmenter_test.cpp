// PersonCropSegmenter and the learned detector's crop masks on a pf2_synth sequence (people
// cut by the border, seated, in dark clothes), scored against its ground-truth labels. The
// model tests skip without the models (scripts/fetch_models.sh).
#include <cstdio>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/detection/crop_segmenter.h"
#include "pf2/detection/learned_models.h"
#include "pf2/detection/learned_person_detector.h"
#include "pf2/detection/pose_refiner.h"
#include "pf2/synth/synthetic_sequence.h"

namespace pf2 {
namespace {

TEST(CropSegmenter, RefusesOptionsOutOfRangeAndMissingModels) {
  PersonCropSegmenter::Options wide;
  wide.margin = 2.5;
  EXPECT_THROW(PersonCropSegmenter segmenter(wide), Error);
  PersonCropSegmenter::Options certain;
  certain.mask_threshold = 1.f;
  EXPECT_THROW(PersonCropSegmenter segmenter(certain), Error);
  for (const int side : {160, 200, 288}) {
    PersonCropSegmenter::Options odd;
    odd.input_size = side;
    EXPECT_THROW(PersonCropSegmenter segmenter(odd), Error) << side;
  }
  PersonCropSegmenter::Options missing;
  missing.model_json = testing::TempDir() + "pf2_no_such_model/blazepose-lite.json";
  try {
    PersonCropSegmenter segmenter(missing);
    ADD_FAILURE() << "no error for a missing model";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(missing.model_json), std::string::npos) << e.what();
  }
}

// The network's input side as the parameter: the model's own 256 and the smallest allowed, 192,
// which runs with its upsamplings' sizes scaled (TfjsGraph::Options::resize_scale).
class CropSegmenterSize : public testing::TestWithParam<int> {};

TEST_P(CropSegmenterSize, MasksLieOnTheCroppedPersonAndStayInTheCrop) {
  if (!humanModelAvailable("blazepose-lite")) GTEST_SKIP() << "no model; run scripts/fetch_models.sh";
  SyntheticSequence::Options synth;
  synth.frames = 30;
  const SyntheticSequence sequence(synth);
  PersonCropSegmenter::Options options;
  options.input_size = GetParam();
  PersonCropSegmenter segmenter(options);
  double on_person = 0, on_people = 0, marked = 0, person_area = 0;
  int crops = 0;
  for (size_t i = 0; i < sequence.size(); i += 3) {
    FrameGroundTruth truth;
    const Frame frame = sequence.frame(i, &truth);
    for (const PersonGroundTruth& person : truth.people) {
      if (person.visible_fraction < 0.3 || person.box.area() < 1500) continue;
      const PersonBox box{static_cast<float>(person.box.x), static_cast<float>(person.box.y),
                          static_cast<float>(person.box.br().x), static_cast<float>(person.box.br().y)};
      const cv::Mat mask = segmenter.segment(frame.rgb, box);
      const cv::Mat mine = truth.labels == person.id;
      const cv::Rect crop = refinementCropPixels(box, 0.25) & cv::Rect(0, 0, mask.cols, mask.rows);
      cv::Mat outside = mask.clone();
      outside(crop).setTo(0);
      EXPECT_EQ(cv::countNonZero(outside), 0) << "frame " << i << " person " << person.id;
      on_person += cv::countNonZero(mask & mine);
      on_people += cv::countNonZero(mask & (truth.labels > 0));  // the crop may hold others too
      marked += cv::countNonZero(mask);
      person_area += cv::countNonZero(mine);
      ++crops;
    }
  }
  ASSERT_GE(crops, 4);
  // Measured: 93.8 / 92.9 % at 256, 93.4 / 91.0 % at 192 (at 160, not allowed, 32 % marked).
  std::printf("input %d: %d crops: %.1f %% of the cropped people marked, %.1f %% of the marks on people\n",
              GetParam(), crops, 100 * on_person / person_area, 100 * on_people / marked);
  EXPECT_GT(on_person / person_area, 0.8);
  EXPECT_GT(on_people / marked, 0.85);
}

INSTANTIATE_TEST_SUITE_P(InputSides, CropSegmenterSize, testing::Values(256, 192));

struct Coverage {
  double people = 0;  // share of the people's pixels inside some person's mask or box-only person
  double rest = 0;    // share of the other pixels inside some person's mask
  double candidate_people = 0;  // the same for the candidates' masks
  double candidate_rest = 0;
};

Coverage learnedCoverage(const SyntheticSequence& sequence, bool crop_masks) {
  LearnedPersonDetector::Options options;
  options.crop_masks = crop_masks;
  LearnedPersonDetector detector(options);
  double hit = 0, people = 0, spill = 0, rest = 0, candidate_hit = 0, candidate_spill = 0;
  for (size_t i = 0; i < sequence.size(); ++i) {
    FrameGroundTruth truth;
    const Frame frame = sequence.frame(i, &truth);
    cv::Mat marked(frame.rgb.size(), CV_8U, cv::Scalar(0)), candidates = marked.clone();
    const Detections detections = detector.detect(frame);
    for (const PersonDetection& p : detections.people)
      if (!p.mask.empty()) marked |= p.mask;
    for (const PersonDetection& c : detections.candidates) candidates |= c.mask;
    const cv::Mat person = truth.labels > 0;
    hit += cv::countNonZero(marked & person);
    people += cv::countNonZero(person);
    spill += cv::countNonZero(marked & ~person);
    candidate_hit += cv::countNonZero(candidates & person);
    candidate_spill += cv::countNonZero(candidates & ~person);
    rest += static_cast<double>(person.total()) - cv::countNonZero(person);
  }
  return {hit / people, spill / rest, candidate_hit / people, candidate_spill / rest};
}

TEST(CropSegmenter, CropMasksCoverMoreOfThePeopleAndLittleElse) {
  if (!humanModelAvailable("blazepose-lite") || !humanModelAvailable("selfie") ||
      !humanModelAvailable("movenet-multipose"))
    GTEST_SKIP() << "no models; run scripts/fetch_models.sh";
  SyntheticSequence::Options synth;
  synth.frames = 36;
  synth.camera = CameraMotion::kHalfsphere;
  const SyntheticSequence sequence(synth);
  const Coverage selfie = learnedCoverage(sequence, false);
  const Coverage crops = learnedCoverage(sequence, true);
  std::printf("people's pixels in a mask: %.1f %% -> %.1f %%; other pixels: %.2f %% -> %.2f %%\n",
              100 * selfie.people, 100 * crops.people, 100 * selfie.rest, 100 * crops.rest);
  EXPECT_GT(crops.people, selfie.people + 0.03);
  EXPECT_LT(crops.rest, selfie.rest + 0.005);
  std::printf("people's pixels in a candidate: %.2f %% -> %.2f %%; other pixels: %.3f %% -> %.3f %%\n",
              100 * selfie.candidate_people, 100 * crops.candidate_people, 100 * selfie.candidate_rest,
              100 * crops.candidate_rest);
  // The candidates cut by the border get crops too (measured 30.7 -> 34.4 %, 0.27 -> 0.42 %).
  EXPECT_GT(crops.candidate_people, selfie.candidate_people + 0.02);
  EXPECT_LT(crops.candidate_rest, selfie.candidate_rest + 0.003);
}

}  // namespace
}  // namespace pf2
