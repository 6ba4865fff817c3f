// Which depths are a person's own when their mask also holds someone else's: for eq. 2's d_m and
// for their body fit.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "pf2/slam/person_centres.h"

namespace pf2 {
namespace {

// A mask the segmentation merged over two people: `front_columns` of the person's 40 x 80 pixel
// area at 2 m (someone in front), the rest at 3 m, all in one interval; the pose's keypoints lie on
// the 3 m part.
struct MergedMask {
  DualBBoxFilter::Person person;
  PersonDetection detection;
  explicit MergedMask(int front_columns) {
    person.detection = 0;
    person.area = cv::Rect(100, 50, 40, 80);
    person.depth = cv::Mat(80, 40, CV_32F, cv::Scalar(3.0f));
    person.depth.colRange(0, front_columns).setTo(2.0f);
    person.interval = {1.9, 3.1, true};
    detection.mask = cv::Mat::zeros(480, 640, CV_8U);
    detection.mask(person.area).setTo(255);
    for (int i = 0; i < 6; ++i) detection.keypoints.push_back({136.f, 60.f + 10 * i, 0.9f});
  }
};

double centreDepth(const MergedMask& scene, const SlamOptions& options) {
  long pixels = 0;
  const double d_m = personCentreDepth(scene.person, &scene.detection, options, &pixels);
  EXPECT_EQ(pixels, 40 * 80);  // every depth of the interval is the person's evidence
  return d_m;
}

TEST(PersonCentreDepth, TakesTheDepthsAroundTheBodyItsKeypointsLieOn) {
  const MergedMask scene(24);  // 60 % at 2 m in front, 40 % at 3 m
  SlamOptions options;
  ASSERT_GT(options.human_joint_band, 0.0);
  EXPECT_NEAR(centreDepth(scene, options), 3.0, 1e-6);
  // Off (and the depth groups off): the interval's mean, between the two people.
  options.human_joint_band = 0.0;
  options.human_group_gap = 0.0;
  EXPECT_NEAR(centreDepth(scene, options), 2.4, 1e-6);
  // Keypoints too unsure to say whose body this is: the interval's mean as well.
  MergedMask unsure(24);
  for (Keypoint2d& k : unsure.detection.keypoints) k.score = 0.1f;
  EXPECT_NEAR(centreDepth(unsure, options), 2.4, 1e-6);
}

// Without keypoints to say whose body a merged mask is, the two people's depths lie 1 m apart with
// none between them: the centre rests on the larger group, on one of them.
TEST(PersonCentreDepth, WithoutABandTheLargestOfTheDepthGroupsIsTheBody) {
  MergedMask scene(24);  // 60 % at 2 m in front, 40 % at 3 m
  for (Keypoint2d& k : scene.detection.keypoints) k.score = 0.1f;
  SlamOptions options;
  ASSERT_GT(options.human_group_gap, 0.0);
  ASSERT_LT(options.human_group_gap, 1.0);
  EXPECT_NEAR(centreDepth(scene, options), 2.0, 1e-6);
  MergedMask behind(16);  // 40 % in front: the person behind is the larger group
  for (Keypoint2d& k : behind.detection.keypoints) k.score = 0.1f;
  EXPECT_NEAR(centreDepth(behind, options), 3.0, 1e-6);
  // Groups nearer each other than the gap are one body.
  options.human_group_gap = 1.1;
  EXPECT_NEAR(centreDepth(scene, options), 2.4, 1e-6);
  // A few stray pixels in the gap (under 1 % of the depths) still part the groups.
  options = SlamOptions();
  scene.person.depth.at<float>(0, 0) = 2.5f;
  scene.person.depth.at<float>(0, 1) = 2.6f;
  EXPECT_NEAR(centreDepth(scene, options), 2.0, 1e-6);
  // The other groups under human_group_min_share of the depths: the interval's mean (the
  // keypoint band handles a sliver; nothing here says the few are someone else).
  const MergedMask sliver(38);  // 95 % at 2 m
  options.human_joint_band = 0.0;
  ASSERT_GT(options.human_group_min_share, 0.05);
  EXPECT_NEAR(centreDepth(sliver, options), 0.95 * 2.0 + 0.05 * 3.0, 1e-6);
}

TEST(PersonCentreDepth, KeypointsOnASliverBehindTheMaskKeepTheIntervalsMean) {
  // The keypoints of a near person cut by the border may land beside them, on a few of the mask's
  // edge pixels at the wall's depth: 10 % of the depths, below human_joint_min_share.
  const MergedMask scene(36);
  SlamOptions options;
  ASSERT_GT(options.human_joint_min_share, 0.1);
  options.human_group_gap = 0.0;
  EXPECT_NEAR(centreDepth(scene, options), 0.9 * 2.0 + 0.1 * 3.0, 1e-6);
  // With the depth groups (the default) the sliver, 1 m behind, is left out.
  EXPECT_NEAR(centreDepth(scene, SlamOptions()), 2.0, 1e-6);
}

// A pose whose keypoints lie off the person's own depth (the person behind them, outside their
// interval) is not theirs to fit.
TEST(KeypointShareOnPerson, CountsTheConfidentKeypointsOnThePersonsDepth) {
  MergedMask scene(24);
  EXPECT_DOUBLE_EQ(keypointShareOnPerson(scene.person, scene.detection, 0.3), 1.0);
  scene.person.depth.colRange(24, 40).setTo(0.f);  // the 3 m part outside this person's interval
  EXPECT_DOUBLE_EQ(keypointShareOnPerson(scene.person, scene.detection, 0.3), 0.0);
  scene.detection.keypoints[0].u = 110.f;  // one keypoint on the near part
  EXPECT_NEAR(keypointShareOnPerson(scene.person, scene.detection, 0.3), 1.0 / 6, 1e-12);
  scene.detection.keypoints[1].u = 125.f;  // 2 px beyond the near part's edge (column 123): on it
  EXPECT_NEAR(keypointShareOnPerson(scene.person, scene.detection, 0.3), 2.0 / 6, 1e-12);
  for (Keypoint2d& k : scene.detection.keypoints) k.score = 0.1f;  // none confident
  EXPECT_DOUBLE_EQ(keypointShareOnPerson(scene.person, scene.detection, 0.3), 1.0);
  scene.detection.keypoints[2] = {-50.f, -50.f, 0.9f};  // outside the image: not on the person
  EXPECT_DOUBLE_EQ(keypointShareOnPerson(scene.person, scene.detection, 0.3), 0.0);
}

TEST(PersonCentreDepth, ABoxWithoutMaskUsesAllItsDepths) {
  const MergedMask scene(24);
  PersonDetection box_only = scene.detection;
  box_only.mask.release();
  long pixels = 0;
  SlamOptions options;
  options.human_group_gap = 0.0;
  EXPECT_NEAR(personCentreDepth(scene.person, &box_only, options, &pixels), 2.4, 1e-6);
  EXPECT_NEAR(personCentreDepth(scene.person, nullptr, options, &pixels), 2.4, 1e-6);
  EXPECT_NEAR(personCentreDepth(scene.person, nullptr, SlamOptions(), &pixels), 2.0, 1e-6);  // the larger group
}

// What the body fit of the scene's person sees, with the band their centre found.
cv::Mat bodyDepthOf(const MergedMask& scene, const SlamOptions& options) {
  long pixels = 0;
  BodyDepthBand band;
  personCentreDepth(scene.person, &scene.detection, options, &pixels, &band);
  return bodyDepth(scene.person, band);
}

TEST(BodyDepth, KeepsOnlyTheDepthsOfTheBodyTheKeypointsLieOn) {
  const MergedMask scene(24);
  const cv::Mat own = bodyDepthOf(scene, SlamOptions());
  ASSERT_EQ(own.size(), scene.person.depth.size());
  EXPECT_EQ(cv::countNonZero(own == 3.0f), 16 * 80);
  EXPECT_EQ(cv::countNonZero(own), 16 * 80);  // the 2 m person in front is gone
  // No band (keypoints on a sliver; or off): the person's depth as the filter left it, shared.
  const MergedMask sliver(36);
  SlamOptions no_groups;
  no_groups.human_group_gap = 0.0;
  EXPECT_EQ(bodyDepthOf(sliver, no_groups).data, sliver.person.depth.data);
  SlamOptions off;
  off.human_joint_band = 0.0;
  off.human_group_gap = 0.0;
  EXPECT_EQ(bodyDepthOf(scene, off).data, scene.person.depth.data);
  // The band off, the depth groups on: the larger group, the 2 m person.
  off.human_group_gap = SlamOptions().human_group_gap;
  EXPECT_EQ(cv::countNonZero(bodyDepthOf(scene, off) == 2.0f), 24 * 80);
  EXPECT_EQ(cv::countNonZero(bodyDepthOf(scene, off)), 24 * 80);
}

// A person seated at 2 m, posed without a mask: their box (100 x 200 pixels) also holds the chair
// beside them at 2.1 m and the wall at 4 m; a patch of their torso reads 3 m (seen past them).
struct SeatedBoxOnly {
  DualBBoxFilter::Person person;
  PersonDetection detection;
  SeatedBoxOnly() {
    person.detection = 0;
    person.box = {200.f, 100.f, 300.f, 300.f};
    person.area = cv::Rect(200, 100, 100, 200);
    person.depth = cv::Mat(200, 100, CV_32F, cv::Scalar(4.0f));
    person.depth(cv::Rect(25, 20, 51, 176)).setTo(2.0f);  // image x 225-275, y 120-295
    person.depth(cv::Rect(80, 80, 20, 80)).setTo(2.1f);   // the chair: x 280-299, y 180-259
    person.depth(cv::Rect(45, 60, 11, 11)).setTo(3.0f);   // x 245-255, y 160-170
    person.mask = person.depth > 0.f;
    detection.keypoints.assign(17, Keypoint2d{0.f, 0.f, 0.f});
    const float u[2] = {235.f, 265.f};
    for (int side = 0; side < 2; ++side) {
      detection.keypoints[5 + side] = {u[side], 130.f, 0.9f};   // shoulders
      detection.keypoints[11 + side] = {u[side], 200.f, 0.9f};  // hips
      detection.keypoints[13 + side] = {u[side], 250.f, 0.9f};  // knees
      detection.keypoints[15 + side] = {u[side], 290.f, 0.9f};  // ankles
    }
  }
};

TEST(PosedBodyDepth, KeepsTheSkeletonsDepthsNotTheChairBesideOrWhatLiesBehind) {
  const SeatedBoxOnly scene;
  const SlamOptions options;
  ASSERT_LT(options.human_joint_band, 0.9);  // the 3 m patch lies outside the band
  const cv::Mat own = posedBodyDepth(scene.person, scene.detection, options);
  ASSERT_EQ(own.size(), scene.person.depth.size());
  EXPECT_FLOAT_EQ(own.at<float>(50, 25), 2.0f);  // the torso, between the shoulders and the hips
  EXPECT_FLOAT_EQ(own.at<float>(170, 35), 2.0f);  // a shin
  EXPECT_EQ(cv::countNonZero(own(cv::Rect(80, 80, 20, 80))), 0);  // the chair
  EXPECT_EQ(cv::countNonZero(own(cv::Rect(45, 60, 11, 11))), 0);  // the 3 m patch
  EXPECT_EQ(cv::countNonZero(own == 4.0f), 0);                    // the wall
  // Only the 2 m body, and most of it: the torso filled, the legs 20 px wide (a tenth of the box).
  EXPECT_EQ(cv::countNonZero(own), cv::countNonZero(own == 2.0f));
  EXPECT_GT(cv::countNonZero(own), 6000);
  // Fewer confident keypoints with depth than filter.joint_min_count: nothing is theirs.
  SeatedBoxOnly unsure;
  for (int i = 5; i < 17; ++i) unsure.detection.keypoints[i].score = i < 7 ? 0.9f : 0.1f;
  ASSERT_GT(options.filter.joint_min_count, 2);
  EXPECT_TRUE(posedBodyDepth(unsure.person, unsure.detection, options).empty());
}

// A person at 2 m seen from above, their mask spilled over the wall behind them: the person's
// dilated mask covers their 260 x 200 pixel area. Columns 40-99 are the body: at 2 m down to row
// 149, the lower legs and feet below at 3.2 m (seen from above, with the knee and ankle keypoints
// on them). Beside the body, columns 0-39 hold the chair they lean on at 2.2 m down to row 99;
// columns 100-115 the wall at 3.5 m down to row 119 (the mask's spill), columns 140-199 a second
// person at 3.5 m the mask took in too, nothing measured between.
struct SpilledMask {
  DualBBoxFilter::Person person;
  Detections detections;
  SpilledMask() {
    person.detection = 0;
    person.area = cv::Rect(100, 100, 260, 200);
    person.box = {140.f, 100.f, 200.f, 300.f};
    person.depth = cv::Mat::zeros(200, 260, CV_32F);
    person.depth(cv::Rect(40, 0, 60, 150)).setTo(2.0f);
    person.depth(cv::Rect(40, 150, 60, 50)).setTo(3.2f);
    person.depth(cv::Rect(0, 0, 40, 100)).setTo(2.2f);
    person.depth(cv::Rect(100, 0, 16, 120)).setTo(3.5f);
    person.depth(cv::Rect(140, 0, 60, 200)).setTo(3.5f);
    person.mask = person.depth > 0.f;
    PersonDetection detection;
    detection.score = 0.9f;
    detection.mask = cv::Mat::zeros(480, 640, CV_8U);
    detection.mask(person.area).setTo(255);
    detection.keypoints.assign(17, Keypoint2d{0.f, 0.f, 0.f});
    detection.keypoints[0] = {170.f, 105.f, 0.9f};  // nose
    const float u[2] = {150.f, 190.f};
    for (int side = 0; side < 2; ++side) {
      detection.keypoints[5 + side] = {u[side], 110.f, 0.9f};   // shoulders
      detection.keypoints[11 + side] = {u[side], 200.f, 0.9f};  // hips
      detection.keypoints[13 + side] = {u[side], 255.f, 0.9f};  // knees, on the 3.2 m lower legs
      detection.keypoints[15 + side] = {u[side], 290.f, 0.9f};  // ankles
    }
    detections.people.push_back(detection);
  }
  cv::Mat behind(double margin) const {
    return depthBehindBodies({person}, detections, SlamOptions(), margin, cv::Size(640, 480))(person.area);
  }
};

TEST(DepthBehindBodies, IsTheSpillOntoTheWallBehindNotTheBodyTheChairOrAPersonFurtherIn) {
  const SpilledMask scene;
  const cv::Mat behind = scene.behind(0.5);
  ASSERT_EQ(behind.size(), scene.person.depth.size());
  // The wall strip next to the body: all of it, and nothing else.
  EXPECT_EQ(cv::countNonZero(behind(cv::Rect(100, 0, 16, 120))), 16 * 120);
  EXPECT_EQ(cv::countNonZero(behind), 16 * 120);
  // The lower legs (1.2 m behind the body's band, 0.8 m is the band's half width plus the margin)
  // lie at their own keypoints' depth; the chair lies in the band; the second person is more
  // than kBehindBodyReach pixels from the body.
  ASSERT_LT(kBehindBodyReach, 140 - 100);
  // A margin wider than the wall lies behind the body: nothing.
  EXPECT_EQ(cv::countNonZero(scene.behind(1.3)), 0);
  // No keypoints to say where the body is: nothing.
  SpilledMask unposed;
  for (Keypoint2d& k : unposed.detections.people[0].keypoints) k.score = 0.1f;
  EXPECT_EQ(cv::countNonZero(unposed.behind(0.5)), 0);
}

// One body seen as two people: the centre of a person behind a near one, whose depths were the
// near one's, lies beside the near one's centre.
TEST(PersonCentres, OfTwoCentresOfOneBodyTheOneOnFewerDepthsIsDropped) {
  DualBBoxFilter::Result filtered;
  filtered.static_depth = cv::Mat::zeros(480, 640, CV_32F);
  const auto add = [&filtered](float x_ul, float y_ul, float x_lr, float y_lr, float depth) {
    DualBBoxFilter::Person person;
    person.box = {x_ul, y_ul, x_lr, y_lr};
    person.area = cv::Rect(cv::Point(cvRound(x_ul), cvRound(y_ul)), cv::Point(cvRound(x_lr), cvRound(y_lr)));
    person.depth = cv::Mat(person.area.size(), CV_32F, cv::Scalar(depth));
    filtered.people.push_back(person);
  };
  add(200, 0, 440, 480, 1.0f);    // the near person, 240 x 480 depths at 1 m
  add(150, 100, 230, 400, 1.0f);  // the one behind, at the near one's depth: centres 0.244 m apart
  add(500, 100, 600, 400, 3.0f);  // someone else, 3 m away
  const CameraIntrinsics K = CameraIntrinsics::tumFreiburg3();
  SlamOptions options;
  const auto kept = [&](double same_body) {
    options.human_same_body = same_body;
    std::vector<size_t> people;
    for (const PersonCentre& centre : personCentres(filtered, Detections(), K, options)) people.push_back(centre.person);
    return people;
  };
  EXPECT_EQ(kept(0.0), (std::vector<size_t>{0, 1, 2}));
  EXPECT_EQ(kept(0.2), (std::vector<size_t>{0, 1, 2}));
  EXPECT_EQ(kept(0.3), (std::vector<size_t>{0, 2}));
  // The larger one stays whichever comes first.
  std::swap(filtered.people[0], filtered.people[1]);
  EXPECT_EQ(kept(0.3), (std::vector<size_t>{1, 2}));
}

// A false mask component the detector joined to a person (the chair at the far side of the image)
// stretches their box across the image; the box of their own depths does not.
TEST(PersonCentres, ABoxStretchedByAFalseMaskComponentKeepsTheCentreOnThePerson) {
  DualBBoxFilter::Result filtered;
  filtered.static_depth = cv::Mat::zeros(480, 640, CV_32F);
  DualBBoxFilter::Person person;
  person.detection = 0;
  person.box = {0, 0, 640, 480};
  person.area = cv::Rect(0, 0, 640, 480);
  person.interval = {1.9, 2.1, true};
  person.depth = cv::Mat::zeros(480, 640, CV_32F);
  person.depth(cv::Rect(100, 50, 80, 400)).setTo(2.0f);  // the person: columns 100-179
  person.depth(cv::Rect(600, 200, 10, 10)).setTo(2.0f);  // 100 stray pixels at their depth
  person.depth(cv::Rect(400, 300, 200, 100)).setTo(4.0f);  // the component, outside the interval
  filtered.people.push_back(person);
  Detections detections;
  detections.people.emplace_back();
  detections.people[0].mask = cv::Mat(480, 640, CV_8U, cv::Scalar(255));
  const CameraIntrinsics K = CameraIntrinsics::tumFreiburg3();
  const double true_x = (140.0 - K.cx) / K.fx * 2.0;
  SlamOptions options;
  ASSERT_TRUE(options.human_box_from_depths);
  std::vector<PersonCentre> centres = personCentres(filtered, detections, K, options);
  ASSERT_EQ(centres.size(), 1u);
  EXPECT_NEAR(centres[0].p_c.x(), true_x, 0.005);
  EXPECT_NEAR(centres[0].p_c.z(), 2.0, 1e-6);
  // Untrimmed, the 100 stray pixels stretch the box to column 609.
  options.human_box_trim = 0.0;
  centres = personCentres(filtered, detections, K, options);
  EXPECT_NEAR(centres[0].p_c.x(), (355.0 - K.cx) / K.fx * 2.0, 0.005);
  // The detector's box (eq. 2 as written): its centre is the image's, 0.67 m beside the person.
  options.human_box_from_depths = false;
  centres = personCentres(filtered, detections, K, options);
  EXPECT_NEAR(centres[0].p_c.x(), (320.0 - K.cx) / K.fx * 2.0, 1e-6);
  EXPECT_GT(std::abs(centres[0].p_c.x() - true_x), 0.6);
}

// One pose took a mask component that spreads far beside the body (the segmenter painted the wall
// behind a seated person): an area 500 x 100 pixels, the person at 3 m in its left part, the wall at
// 4 m. Their confident keypoints (COCO order) are the shoulders and elbows, u 110-130, v 60-120:
// the region their body may fill is that box grown by a quarter (5 pixels) to the sides and 15
// pixels up, and down to the image's bottom, since no ankle is among them. That is under a tenth of
// the depths, and the rest lies behind, so it is cleared for placing and fitting them.
TEST(OwnParts, ClearsTheWallBesideThePosesBody) {
  const cv::Rect body = cv::Rect(cv::Point(105, 50), cv::Point(136, 150));  // image pixels
  DualBBoxFilter::Person wide;
  wide.detection = 0;
  wide.area = cv::Rect(100, 50, 500, 100);
  wide.depth = cv::Mat(100, 500, CV_32F, cv::Scalar(4.0f));
  wide.depth(body - wide.area.tl()).setTo(3.0f);
  wide.mask = cv::Mat(100, 500, CV_8U, cv::Scalar(255));
  Detections detections;
  detections.people.emplace_back();
  std::vector<Keypoint2d>& keypoints = detections.people[0].keypoints;
  keypoints.assign(17, Keypoint2d{0.f, 0.f, 0.1f});
  keypoints[5] = {110.f, 60.f, 0.9f};   // left shoulder
  keypoints[6] = {130.f, 60.f, 0.9f};   // right shoulder
  keypoints[7] = {110.f, 120.f, 0.9f};  // left elbow
  keypoints[8] = {130.f, 120.f, 0.9f};  // right elbow
  SlamOptions options;
  options.human_max_outside_pose = 0.7;
  std::vector<DualBBoxFilter::Person> own = ownParts({wide}, detections, options);
  ASSERT_EQ(own.size(), 1u);
  const cv::Rect kept = body - wide.area.tl();
  EXPECT_EQ(cv::countNonZero(own[0].depth > 0.f), kept.area());
  EXPECT_EQ(cv::countNonZero(own[0].depth(kept) == 3.0f), kept.area());
  EXPECT_EQ(cv::countNonZero(own[0].mask), kept.area());
  EXPECT_EQ(cv::countNonZero(wide.depth > 0.f), 500 * 100);  // the filter's person is left alone

  // With an ankle confident the body ends a quarter of the box's height below it.
  keypoints[15] = {120.f, 100.f, 0.9f};
  own = ownParts({wide}, detections, options);
  const cv::Rect to_ankle = cv::Rect(cv::Point(105, 50), cv::Point(136, 136)) - wide.area.tl();
  EXPECT_EQ(cv::countNonZero(own[0].depth > 0.f), to_ankle.area());
  EXPECT_EQ(cv::countNonZero(own[0].depth(to_ankle) > 0.f), to_ankle.area());
  keypoints[15].score = 0.1f;

  // What lies outside at the body's depth is more of the body, and what lies in front is someone
  // else: neither is cut off (nor is anything 0.3 m behind, within human_joint_band).
  for (const float rest : {3.0f, 2.0f, 3.25f}) {
    cv::Mat depth(100, 500, CV_32F, cv::Scalar(rest));
    depth(kept).setTo(3.0f);
    DualBBoxFilter::Person same = wide;
    same.depth = depth;
    EXPECT_EQ(ownParts({same}, detections, options)[0].depth.data, depth.data) << "rest at " << rest << " m";
  }
  // Off, or a person mostly inside their region: as they were, sharing the filter's images.
  options.human_max_outside_pose = 1.0;
  EXPECT_EQ(ownParts({wide}, detections, options)[0].depth.data, wide.depth.data);
  options.human_max_outside_pose = 0.95;
  EXPECT_EQ(ownParts({wide}, detections, options)[0].depth.data, wide.depth.data);
  // Fewer confident keypoints than the filter's joint_min_count: nothing to tell the body by.
  options.human_max_outside_pose = 0.7;
  for (size_t k = 6; k <= 8; ++k) keypoints[k].score = 0.1f;
  EXPECT_EQ(ownParts({wide}, detections, options)[0].depth.data, wide.depth.data);
}

}  // namespace
}  // namespace pf2
