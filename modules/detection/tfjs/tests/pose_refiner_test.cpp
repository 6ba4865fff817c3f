// PoseRefiner: the crop's geometry (no model needed), and on a generated sequence with three
// people whether the keypoints of the closer look lie nearer the people's true joints than the
// whole-frame pass's. The second test skips without the models (scripts/fetch_models.sh).
#include <algorithm>
#include <limits>

#include <gtest/gtest.h>

#include "pf2/body/body_fitter.h"
#include "pf2/core/error.h"
#include "pf2/core/median.h"
#include "pf2/detection/learned_models.h"
#include "pf2/detection/movenet_detector.h"
#include "pf2/detection/pose_refiner.h"
#include "pf2/synth/synthetic_sequence.h"

namespace pf2 {
namespace {

double median(std::vector<double> values) { return upperMedian(&values); }

TEST(PoseRefiner, CropIsASquareAroundTheBoxWithTheMargin) {
  const cv::Rect2f crop = refinementCrop({100, 50, 140, 250}, 0.1);  // 40 x 200 px
  EXPECT_FLOAT_EQ(crop.width, 220.f);
  EXPECT_FLOAT_EQ(crop.height, 220.f);
  EXPECT_FLOAT_EQ(crop.x + crop.width / 2, 120.f);
  EXPECT_FLOAT_EQ(crop.y + crop.height / 2, 150.f);
}

TEST(PoseRefiner, RefusesOptionsOutOfRange) {
  PoseRefiner::Options options;
  options.input_size = 100;  // not a multiple of 32
  EXPECT_THROW(PoseRefiner{options}, Error);
  options = {};
  options.margin = -0.1;
  EXPECT_THROW(PoseRefiner{options}, Error);
}

// Pixel distance of each confident limb keypoint to its true joint, for the person whose joints
// the whole-frame keypoints lie nearest to.
void keypointErrors(const std::vector<Keypoint2d>& whole, const std::vector<Keypoint2d>& refined,
                    const std::vector<std::vector<Eigen::Vector2d>>& people_px, std::vector<double>* whole_errors,
                    std::vector<double>* refined_errors) {
  constexpr int kFirstLimbKeypoint = 5;  // shoulders to ankles; the face's keypoints have no joint of their own
  double best = std::numeric_limits<double>::max();
  const std::vector<Eigen::Vector2d>* person = nullptr;
  for (const auto& joints : people_px) {
    std::vector<double> d;
    for (int k = kFirstLimbKeypoint; k < kCocoKeypointCount; ++k)
      d.push_back((joints[kCocoToBodyJoint[k].joint] - Eigen::Vector2d(whole[k].u, whole[k].v)).norm());
    if (median(d) < best) best = median(d), person = &joints;
  }
  for (int k = kFirstLimbKeypoint; k < kCocoKeypointCount; ++k) {
    if (whole[k].score < 0.3f || refined[k].score < 0.3f) continue;
    const Eigen::Vector2d& joint = (*person)[kCocoToBodyJoint[k].joint];
    whole_errors->push_back((joint - Eigen::Vector2d(whole[k].u, whole[k].v)).norm());
    refined_errors->push_back((joint - Eigen::Vector2d(refined[k].u, refined[k].v)).norm());
  }
}

TEST(PoseRefiner, KeypointsLieNearerTheTrueJointsThanTheWholeFramePasses) {
  if (!humanModelAvailable("movenet-multipose")) GTEST_SKIP() << "no models; run scripts/fetch_models.sh";
  SyntheticSequence::Options synth;
  synth.frames = 60;
  synth.people = 3;
  synth.camera = CameraMotion::kXyz;
  const SyntheticSequence sequence(synth);
  MoveNetDetector movenet({});
  PoseRefiner refiner({});
  std::vector<double> whole_errors, refined_errors;
  int refined_people = 0;
  for (size_t i = 0; i < sequence.size(); i += 4) {
    const Frame frame = sequence.frame(i);
    const Eigen::Isometry3d T_c_w = sequence.pose(i).inverse();
    std::vector<std::vector<Eigen::Vector2d>> people_px;
    for (const BodyMesh& body : sequence.bodies(i)) {
      std::vector<Eigen::Vector2d> joints;
      for (const Eigen::Vector3d& j : body.joints) joints.push_back(frame.intrinsics.project(T_c_w * j));
      people_px.push_back(joints);
    }
    for (const PersonDetection& person : movenet.detect(frame).people) {
      std::vector<Keypoint2d> refined = person.keypoints;
      if (!refiner.refine(frame.rgb, person.box, &refined)) continue;
      ++refined_people;
      keypointErrors(person.keypoints, refined, people_px, &whole_errors, &refined_errors);
    }
  }
  ASSERT_GE(refined_people, 10);
  ASSERT_GE(whole_errors.size(), 100u);
  // MoveNet marks surface landmarks, a few pixels beside the joints, in both passes alike.
  EXPECT_LT(median(refined_errors), 0.85 * median(whole_errors))
      << "median px: whole frame " << median(whole_errors) << ", refined " << median(refined_errors);
}

}  // namespace
}  // namespace pf2
