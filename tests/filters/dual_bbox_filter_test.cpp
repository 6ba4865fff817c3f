#include "pf2/filters/dual_bbox_filter.h"

#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

int differing(const cv::Mat& a, const cv::Mat& b) {
  cv::Mat diff = a != b;
  return cv::countNonZero(diff.reshape(1));
}

PersonDetection person(float x_ul, float y_ul, float x_lr, float y_lr, float score = 0.9f) {
  PersonDetection p;
  p.box = PersonBox{x_ul, y_ul, x_lr, y_lr};
  p.score = score;
  return p;
}

// The hand-made scenes are small: a 0.4 m person window grown by bins >= 25 % keeps the numbers
// below easy to check by hand (the defaults are tuned for whole bodies, see docs/filters.md).
DualBBoxFilter::Options testOptions() {
  DualBBoxFilter::Options o;
  o.human_histogram = HistogramOptions{0.05, 10.0, 0.4, 0.25, 0.6};
  return o;
}

Detections detections(std::vector<PersonDetection> people) {
  Detections d;
  d.people = std::move(people);
  return d;
}

// A 40x30 scene: wall at 3.02 m, a person (cols 15..24, rows 10..24) at 1.52 m whose box is
// (14, 9)-(26, 26); the lambda = 1.2 ring is cols 13..26, rows 7..27.
struct Scene {
  cv::Mat depth = cv::Mat(30, 40, CV_32F, cv::Scalar(3.02f));
  Scene() {
    depth(cv::Rect(15, 10, 10, 15)).setTo(1.52f);
    depth.at<float>(12, 13) = 1.6f;   // arm outside the box, inside the ring: removed (line 11)
    depth.at<float>(13, 10) = 1.6f;   // arm outside the ring: kept (the paper cannot see it)
    depth.at<float>(8, 20) = 3.12f;   // static object in the ring, like the background: kept
    depth.at<float>(27, 20) = 2.5f;   // ring depth unlike the background: removed (line 11)
    depth.at<float>(20, 16) = 1.9f;   // in the box, beyond h_max + 0.2: given back (line 13)
    depth.at<float>(11, 18) = 0.f;    // no measurement stays none
  }
};

// The Scene's person boxed, with a segmenter's mask over the upper body only (cols 15..20, rows
// 10..21), and the filter's options for masks dilated by one pixel.
PersonDetection upperBodyMasked() {
  PersonDetection p = person(14, 9, 26, 26);
  p.mask = cv::Mat::zeros(30, 40, CV_8U);
  p.mask(cv::Rect(15, 10, 6, 12)).setTo(255);
  return p;
}

DualBBoxFilter::Options maskOptions() {
  DualBBoxFilter::Options o = testOptions();
  o.use_mask = true;
  o.mask_dilation = 1;
  return o;
}

TEST(PrincipalInterval, NearestLargeWindowGrownByNeighbours) {
  // 100 px at 1.52 m, 30 px at 1.62 m (neighbour of the window... two bins away), 160 px at 3.02 m.
  cv::Mat depth(1, 290, CV_32F);
  for (int i = 0; i < 290; ++i) depth.at<float>(0, i) = i < 100 ? 1.52f : i < 130 ? 1.62f : 3.02f;
  HistogramOptions o{0.05, 10.0, 0.4, 0.25, 0.6};  // bins, max depth, window, grow, near preference
  const DepthInterval near = principalInterval(depth, cv::Mat(), cv::Rect(0, 0, 290, 1), o);
  ASSERT_TRUE(near.valid);
  // 130 >= 0.6 x 160: the person's window wins over the wall; it spans bins 30 and 32.
  EXPECT_NEAR(near.min, 1.50, 1e-9);
  EXPECT_NEAR(near.max, 1.65, 1e-9);
  o.near_preference = 1.0;  // plain maximum: the wall
  const DepthInterval far = principalInterval(depth, cv::Mat(), cv::Rect(0, 0, 290, 1), o);
  EXPECT_NEAR(far.min, 3.00, 1e-9);
  EXPECT_NEAR(far.max, 3.05, 1e-9);
  // A window of one bin grows into a neighbour holding >= 25 % of it, not into one holding less.
  o.window = 0.05;
  cv::Mat two(1, 10, CV_32F, cv::Scalar(2.02f));
  two.at<float>(0, 0) = 2.07f;  // 1 of 9 = 11 %: not grown
  two.at<float>(0, 1) = 1.97f;
  two.at<float>(0, 2) = 1.97f;
  two.at<float>(0, 3) = 1.97f;  // 3 of 6... counts: 2.0x bin 6 px, 1.9x bin 3 px = 50 %: grown
  const DepthInterval grown = principalInterval(two, cv::Mat(), cv::Rect(0, 0, 10, 1), o);
  EXPECT_NEAR(grown.min, 1.95, 1e-9);
  EXPECT_NEAR(grown.max, 2.05, 1e-9);
}

TEST(PrincipalInterval, MaskRoiAndInvalidDepths) {
  cv::Mat depth(2, 4, CV_32F, cv::Scalar(1.02f));
  depth.at<float>(0, 0) = std::numeric_limits<float>::quiet_NaN();
  depth.at<float>(0, 1) = 12.f;  // beyond max_depth
  depth.at<float>(1, 3) = 4.02f;
  cv::Mat mask = cv::Mat::zeros(2, 4, CV_8U);
  mask.at<uint8_t>(1, 3) = 1;
  HistogramOptions o{0.05, 10.0, 0.4, 0.25, 0.6};
  const DepthInterval masked = principalInterval(depth, mask, cv::Rect(0, 0, 4, 2), o);
  ASSERT_TRUE(masked.valid);
  EXPECT_NEAR(masked.min, 4.0, 1e-9);
  EXPECT_FALSE(principalInterval(depth, cv::Mat(), cv::Rect(0, 0, 2, 1), o).valid);  // NaN + 12 m only
  EXPECT_FALSE(principalInterval(depth, cv::Mat(), cv::Rect(10, 10, 3, 3), o).valid);  // outside
}

TEST(PrincipalInterval, SurroundContrastKeepsTheWallFromWinning) {
  // A 10x10 box holding 30 px of a person at 1.2 m and 70 px of wall at 4.0 m; the surround (the
  // 20x20 square around it) is all wall: 300 px outside the box.
  cv::Mat depth(20, 20, CV_32F, cv::Scalar(4.0f));
  const cv::Rect box(5, 5, 10, 10), surround(0, 0, 20, 20);
  depth(cv::Rect(5, 5, 3, 10)).setTo(1.2f);
  HistogramOptions o{0.05, 10.0, 0.4, 0.25, 0.6};
  // Plain counts: 30 < 0.6 x 70, so the wall wins.
  const DepthInterval plain = principalInterval(depth, cv::Mat(), box, o, surround);
  ASSERT_TRUE(plain.valid);
  EXPECT_NEAR(plain.min, 4.0, 1e-9);
  // Weight 0.5: the wall bin loses 0.5 x (100 / 300) x 300 = 50 of its 70; the person's 30 win.
  o.surround_weight = 0.5;
  const DepthInterval contrasted = principalInterval(depth, cv::Mat(), box, o, surround);
  ASSERT_TRUE(contrasted.valid);
  EXPECT_NEAR(contrasted.min, 1.2, 1e-9);
  EXPECT_NEAR(contrasted.max, 1.25, 1e-9);
  // Without a surround the weight does nothing.
  EXPECT_NEAR(principalInterval(depth, cv::Mat(), box, o).min, 4.0, 1e-9);
}

TEST(DualBBoxFilter, OccludedPersonInsideANearerPersonsBoxIsRemoved) {
  // A 60x40 scene at 5 m. Person A at 1.0 m fills cols 0..29, rows 20..39 (box (0,20)-(30,40));
  // person B at 3.0 m stands behind, cols 10..19, rows 5..19 visible (box (10,5)-(20,35), its
  // lower half covered by A). B's box holds 150 px of A and 150 px of B: both boxes find A.
  cv::Mat depth(40, 60, CV_32F, cv::Scalar(5.0f));
  depth(cv::Rect(10, 5, 10, 15)).setTo(3.0f);
  depth(cv::Rect(0, 20, 30, 20)).setTo(1.0f);
  const Detections people = detections({person(0, 20, 30, 40), person(10, 5, 20, 35)});
  DualBBoxFilter::Options o = testOptions();
  o.separate_occlusions = false;
  const auto alone = DualBBoxFilter(o).filter(depth, people);
  const cv::Rect b_visible(10, 5, 10, 15);
  EXPECT_EQ(cv::countNonZero(alone.removed(b_visible)), 0);  // B given back: its box found A
  o.separate_occlusions = true;
  const auto separated = DualBBoxFilter(o).filter(depth, people);
  EXPECT_EQ(cv::countNonZero(separated.removed(b_visible)), 150);  // A fills 100 % of its box, 50 % of B's
  EXPECT_EQ(cv::countNonZero(separated.removed(cv::Rect(0, 20, 30, 20))), 600);  // A still removed
  ASSERT_EQ(separated.people.size(), 2u);
  EXPECT_NEAR(separated.people[1].interval.min, 1.0, 1e-9);  // B's first interval is kept as found
  EXPECT_EQ(cv::countNonZero(separated.removed), 750);       // nothing else: the wall stays
}

TEST(DualBBoxFilter, Algorithm1OnHandMadeScene) {
  const Scene scene;
  DualBBoxFilter filter(testOptions());
  const auto result = filter.filter(scene.depth, detections({person(14, 9, 26, 26)}));

  cv::Mat expected_static = scene.depth.clone();
  cv::Mat expected_person = cv::Mat::zeros(30, 40, CV_32F);
  scene.depth(cv::Rect(15, 10, 10, 15)).copyTo(expected_person(cv::Rect(15, 10, 10, 15)));
  expected_person.at<float>(20, 16) = 0.f;  // given back to the background
  expected_static.setTo(0.f, expected_person > 0);
  expected_static.at<float>(12, 13) = 0.f;
  expected_static.at<float>(27, 20) = 0.f;

  ASSERT_EQ(result.people.size(), 1u);
  EXPECT_EQ(differing(result.static_depth, expected_static), 0);
  EXPECT_EQ(result.people[0].area, cv::Rect(14, 9, 12, 17));
  EXPECT_EQ(differing(result.people[0].fullDepth(scene.depth.size()), expected_person), 0);
  EXPECT_EQ(differing(result.people[0].fullMask(scene.depth.size()), expected_person > 0), 0);
  cv::Mat expected_removed = (scene.depth > 0) & (expected_static == 0);
  EXPECT_EQ(differing(result.removed, expected_removed), 0);
  EXPECT_NEAR(result.people[0].interval.min, 1.50, 1e-9);
  EXPECT_NEAR(result.people[0].interval.max, 1.55, 1e-9);
  EXPECT_NEAR(result.background.min, 3.00, 1e-9);
  EXPECT_NEAR(result.background.max, 3.15, 1e-9);
  EXPECT_EQ(result.static_depth.at<float>(13, 10), 1.6f);  // outside the ring
  EXPECT_EQ(result.static_depth.at<float>(8, 20), 3.12f);
  EXPECT_EQ(result.static_depth.at<float>(20, 16), 1.9f);
}

TEST(DualBBoxFilter, BoxesAtOrBelowConfidenceAreIgnored) {
  const Scene scene;
  DualBBoxFilter filter(testOptions());
  const auto result = filter.filter(scene.depth, detections({person(14, 9, 26, 26, 0.5f)}));
  EXPECT_TRUE(result.people.empty());
  EXPECT_EQ(differing(result.static_depth, scene.depth), 0);
}

TEST(DualBBoxFilter, LambdaOneHasNoRing) {
  const Scene scene;
  DualBBoxFilter::Options o = testOptions();
  o.box_scale = 1.0;
  DualBBoxFilter filter(o);
  const auto result = filter.filter(scene.depth, detections({person(14, 9, 26, 26)}));
  EXPECT_EQ(result.static_depth.at<float>(12, 13), 1.6f);
  EXPECT_EQ(result.static_depth.at<float>(27, 20), 2.5f);
  EXPECT_EQ(result.static_depth.at<float>(15, 18), 0.f);
}

TEST(DualBBoxFilter, OverlappingPeopleDoNotGiveEachOtherBack) {
  // Two people at 1.52 m and 2.52 m whose boxes overlap: each box holds part of the other person;
  // the literal loop of Algorithm 1 would give the first person's pixels back in the second box.
  cv::Mat depth(30, 40, CV_32F, cv::Scalar(4.02f));
  depth(cv::Rect(5, 5, 10, 20)).setTo(1.52f);
  depth(cv::Rect(15, 5, 10, 20)).setTo(2.52f);
  DualBBoxFilter filter(testOptions());
  const auto result = filter.filter(depth, detections({person(4, 4, 16, 26), person(12, 4, 26, 26)}));
  ASSERT_EQ(result.people.size(), 2u);
  EXPECT_EQ(cv::countNonZero(result.static_depth(cv::Rect(5, 5, 20, 20))), 0);
  EXPECT_EQ(cv::countNonZero(result.people[0].mask), 200);
  EXPECT_EQ(cv::countNonZero(result.people[1].mask), 200);
}

// A person at 2.02 m beside and behind a person at 1.02 m, each with a mask and keypoints; the
// split of the detector's shared mask handed the far person 140 of the near person's pixels
// against 90 of their own, so the far mask's principal depth is the near person's.
struct SharedMaskScene {
  cv::Mat depth = cv::Mat(30, 40, CV_32F, cv::Scalar(3.02f));
  PersonDetection near_person = person(4, 4, 25, 30), far_person = person(17, 7, 33, 28);
  SharedMaskScene() {
    depth(cv::Rect(5, 5, 20, 25)).setTo(1.02f);
    depth(cv::Rect(26, 10, 6, 15)).setTo(2.02f);
    near_person.mask = cv::Mat::zeros(depth.size(), CV_8U);
    near_person.mask(cv::Rect(5, 5, 13, 25)).setTo(255);
    far_person.mask = cv::Mat::zeros(depth.size(), CV_8U);
    far_person.mask(cv::Rect(18, 8, 7, 20)).setTo(255);
    far_person.mask(cv::Rect(26, 10, 6, 15)).setTo(255);
    for (int i = 0; i < 5; ++i) {
      near_person.keypoints.push_back({8.f + 2 * i, 8.f + 4 * i, 0.9f});
      far_person.keypoints.push_back({27.f + i, 11.f + 3 * i, 0.9f});
    }
  }
};

TEST(DualBBoxFilter, MaskedPersonBehindANearerOneGetsTheDepthUnderTheirJoints) {
  const SharedMaskScene scene;
  DualBBoxFilter::Options o = testOptions();
  o.use_mask = true;
  o.mask_dilation = 0;
  o.joint_min_count = 0;  // off: the interval the mask alone gives
  auto people = DualBBoxFilter(o).filter(scene.depth, detections({scene.near_person, scene.far_person})).people;
  ASSERT_EQ(people.size(), 2u);
  EXPECT_TRUE(people[1].interval.contains(1.02, 0.0));
  o.joint_min_count = 3;
  people = DualBBoxFilter(o).filter(scene.depth, detections({scene.near_person, scene.far_person})).people;
  ASSERT_EQ(people.size(), 2u);
  EXPECT_TRUE(people[0].interval.contains(1.02, 0.0));
  EXPECT_TRUE(people[1].interval.contains(2.02, 0.0));
  EXPECT_FALSE(people[1].interval.contains(1.02, o.human_margin));
  EXPECT_EQ(cv::countNonZero(people[1].fullDepth(scene.depth.size()) == 2.02f), 90);
  // Too few confident joints: the mask's interval stays.
  PersonDetection unsure = scene.far_person;
  for (size_t i = 2; i < unsure.keypoints.size(); ++i) unsure.keypoints[i].score = 0.1f;
  people = DualBBoxFilter(o).filter(scene.depth, detections({scene.near_person, unsure})).people;
  EXPECT_TRUE(people[1].interval.contains(1.02, 0.0));
}

TEST(DualBBoxFilter, JointsBehindALonePersonDoNotMoveTheirInterval) {
  // The joints of a near person cut by the border often land on what is behind them; with no
  // other person at the mask's depth the mask's interval is kept.
  SharedMaskScene scene;
  for (Keypoint2d& k : scene.near_person.keypoints) k.u += 25.f;  // on the wall at 3.02 m
  scene.near_person.mask(cv::Rect(4, 5, 1, 25)).setTo(255);  // the mask's edge takes in some wall
  DualBBoxFilter::Options o = testOptions();
  o.use_mask = true;
  const auto people = DualBBoxFilter(o).filter(scene.depth, detections({scene.near_person})).people;
  ASSERT_EQ(people.size(), 1u);
  EXPECT_TRUE(people[0].interval.contains(1.02, 0.0));
}

TEST(DualBBoxFilter, DegenerateInputs) {
  const Scene scene;
  DualBBoxFilter filter(testOptions());
  // Empty box (zero width) and a box with corners swapped: no person, nothing changes.
  auto r = filter.filter(scene.depth, detections({person(20, 10, 20, 25), person(25, 25, 15, 10)}));
  EXPECT_TRUE(r.people.empty());
  EXPECT_EQ(differing(r.static_depth, scene.depth), 0);
  // Entirely outside the image.
  r = filter.filter(scene.depth, detections({person(100, 100, 120, 140)}));
  EXPECT_TRUE(r.people.empty());
  // Partly outside: clipped; the person's pixels inside the image are removed.
  cv::Mat edge(30, 40, CV_32F, cv::Scalar(3.02f));
  edge(cv::Rect(30, 10, 10, 15)).setTo(1.52f);
  r = filter.filter(edge, detections({person(29, 9, 60, 26)}));
  ASSERT_EQ(r.people.size(), 1u);
  EXPECT_EQ(r.people[0].box.x_lr, 40.f);
  EXPECT_EQ(cv::countNonZero(r.people[0].mask), 150);
  EXPECT_EQ(cv::countNonZero(r.static_depth(cv::Rect(30, 10, 10, 15))), 0);
  // One-pixel box: that pixel is the person.
  r = filter.filter(scene.depth, detections({person(20, 15, 21, 16)}));
  ASSERT_EQ(r.people.size(), 1u);
  EXPECT_EQ(cv::countNonZero(r.people[0].mask), 1);
  EXPECT_EQ(r.static_depth.at<float>(15, 20), 0.f);
  // All-zero depth: nothing to keep, nothing to remove, intervals invalid.
  r = filter.filter(cv::Mat::zeros(30, 40, CV_32F), detections({person(14, 9, 26, 26)}));
  EXPECT_EQ(cv::countNonZero(r.static_depth), 0);
  EXPECT_EQ(cv::countNonZero(r.removed), 0);
  EXPECT_FALSE(r.background.valid);
  // NaN and negative depths are no measurement: zero in the output, never removed.
  cv::Mat nan = scene.depth.clone();
  nan.at<float>(0, 0) = std::numeric_limits<float>::quiet_NaN();
  nan.at<float>(15, 18) = std::numeric_limits<float>::quiet_NaN();
  nan.at<float>(1, 1) = -1.f;
  r = filter.filter(nan, detections({person(14, 9, 26, 26)}));
  EXPECT_EQ(r.static_depth.at<float>(0, 0), 0.f);
  EXPECT_EQ(r.static_depth.at<float>(1, 1), 0.f);
  EXPECT_EQ(r.removed.at<uint8_t>(0, 0), 0);
  EXPECT_EQ(r.removed.at<uint8_t>(15, 18), 0);
  EXPECT_EQ(cv::countNonZero(r.people[0].mask), 147);  // 150 - 1.9 m - no depth - NaN
  // Wrong image type.
  EXPECT_THROW(filter.filter(cv::Mat::zeros(30, 40, CV_16U), detections({})), Error);
  EXPECT_THROW(filter.filter(cv::Mat(), detections({})), Error);
}

TEST(DualBBoxFilter, MaskAdditionRemovesMaskedPixelsOutsideTheBox) {
  const Scene scene;
  PersonDetection p = person(14, 9, 26, 26);
  p.mask = cv::Mat::zeros(30, 40, CV_8U);
  p.mask(cv::Rect(15, 10, 10, 15)).setTo(255);
  p.mask.at<uint8_t>(13, 11) = 255;  // the arm outside the ring, as a segmenter would see it
  DualBBoxFilter::Options o = testOptions();
  DualBBoxFilter plain(o);
  EXPECT_EQ(plain.filter(scene.depth, detections({p})).static_depth.at<float>(13, 10), 1.6f);
  o.use_mask = true;
  o.mask_dilation = 1;
  DualBBoxFilter with_mask(o);
  const auto r = with_mask.filter(scene.depth, detections({p}));
  EXPECT_EQ(r.static_depth.at<float>(13, 10), 0.f);  // within one pixel of the mask
  EXPECT_EQ(r.people[0].fullMask(scene.depth.size()).at<uint8_t>(13, 10), 255);
  EXPECT_EQ(r.people[0].area, cv::Rect(10, 9, 16, 17));  // box joined with the dilated mask
  EXPECT_EQ(r.static_depth.at<float>(13, 8), 3.02f);  // two pixels away: kept
  // The masked histogram excludes the 1.9 m pixel's bin from consideration; the interval is the body's.
  EXPECT_NEAR(r.people[0].interval.min, 1.50, 1e-9);
}

TEST(DualBBoxFilter, TemporalAdditionGuardsAMissedPersonForMaxAgeFrames) {
  const Scene scene;
  DualBBoxFilter::Options o = testOptions();
  o.temporal = true;
  o.temporal_guard.dilation = 1;
  o.temporal_guard.max_age = 2;
  DualBBoxFilter filter(o);
  filter.setIntrinsics(CameraIntrinsics{30, 30, 20, 15, 40, 30});
  filter.filter(scene.depth, detections({person(14, 9, 26, 26)}));
  // Next frames: the detector misses the person; the still camera sees them where they were.
  for (int frame = 1; frame <= 2; ++frame) {
    const auto r = filter.filter(scene.depth, detections({}));
    // Only the 1.9 m pixel, given back in the first frame and unlike its neighbours, remains.
    EXPECT_EQ(cv::countNonZero(r.static_depth(cv::Rect(15, 10, 10, 15))), 1) << "frame " << frame;
    EXPECT_EQ(r.static_depth.at<float>(20, 16), 1.9f);
    EXPECT_EQ(r.static_depth.at<float>(5, 5), 3.02f);  // far from the person: kept
    EXPECT_EQ(r.static_depth.at<float>(16, 26), 3.02f); // next to the person but at the wall: kept
  }
  const auto old = filter.filter(scene.depth, detections({}));  // older than max age: let go
  EXPECT_EQ(differing(old.static_depth, scene.depth), 0);
  // Camera motion moves the guard: the camera moved 0.1 m to the left (scene moves right in
  // the image by fx * 0.1 / 1.52 = ~2 px for the person).
  DualBBoxFilter moving(o);
  moving.setIntrinsics(CameraIntrinsics{30, 30, 20, 15, 40, 30});
  moving.filter(scene.depth, detections({person(14, 9, 26, 26)}));
  Eigen::Isometry3d T_cur_prev = Eigen::Isometry3d::Identity();
  T_cur_prev.translation() = Eigen::Vector3d(0.1, 0, 0);
  cv::Mat shifted(30, 40, CV_32F, cv::Scalar(3.02f));
  shifted(cv::Rect(17, 10, 10, 15)).setTo(1.52f);
  const auto r = moving.filter(shifted, detections({}), T_cur_prev);
  EXPECT_EQ(cv::countNonZero(r.static_depth(cv::Rect(17, 10, 10, 15))), 0);
}

// outside_masks_tracker_only: what the box, ring and temporal rules removed outside every mask
// stays in D_b for the map and is reported in kept_for_map_only (the tracker leaves it out); a
// person without a mask keeps their box's labels, and what the dynamic evidence marks stays removed.
TEST(DualBBoxFilter, OutsideMasksTrackerOnlyKeepsTheGuardAndRingForTheMap) {
  const Scene scene;
  const cv::Rect body(15, 10, 10, 15);
  DualBBoxFilter::Options o = testOptions();
  o.temporal = true;
  o.temporal_guard.dilation = 1;
  // Two frames, the person boxed (no mask) in the first and missed in the second (the guard's).
  auto run = [&](bool tracker_only, DualBBoxFilter::Result* boxed) {
    o.outside_masks_tracker_only = tracker_only;
    DualBBoxFilter filter(o);
    filter.setIntrinsics(CameraIntrinsics{30, 30, 20, 15, 40, 30});
    *boxed = filter.filter(scene.depth, detections({person(14, 9, 26, 26)}));
    EXPECT_EQ(cv::countNonZero(boxed->static_depth(body)), 1);  // the box took the body
    return filter.filter(scene.depth, detections({}));
  };
  DualBBoxFilter::Result boxed_removed, boxed_kept;
  const auto removed = run(false, &boxed_removed);
  const int guarded = cv::countNonZero(removed.removed);
  EXPECT_GE(cv::countNonZero(removed.removed(body)), body.area() - 2);  // all but 1.9 m and no depth
  const auto kept = run(true, &boxed_kept);
  // The boxed frame: the ring rule's two outliers (1.6 m at row 12, 2.5 m at row 27) go to the map.
  ASSERT_FALSE(boxed_kept.kept_for_map_only.empty());
  EXPECT_EQ(cv::countNonZero(boxed_kept.kept_for_map_only), 2);
  EXPECT_EQ(boxed_kept.kept_for_map_only.at<uint8_t>(12, 13), 255);
  EXPECT_EQ(boxed_kept.kept_for_map_only.at<uint8_t>(27, 20), 255);
  EXPECT_EQ(cv::countNonZero(boxed_kept.removed), cv::countNonZero(boxed_removed.removed) - 2);
  // The guard's frame: all it took goes to the map.
  EXPECT_EQ(cv::countNonZero(kept.removed), 0);
  EXPECT_EQ(differing(kept.static_depth, scene.depth), 0);
  ASSERT_FALSE(kept.kept_for_map_only.empty());
  EXPECT_EQ(cv::countNonZero(kept.kept_for_map_only), guarded);
  EXPECT_EQ(cv::countNonZero(kept.kept_for_map_only != removed.removed), 0);
  // With evidence that the body stands in front of the wall, the guarded body stays removed.
  auto evidence = std::make_shared<PredictedDepthEvidence>(0.15);
  evidence->setPrediction(cv::Mat(30, 40, CV_32F, cv::Scalar(3.02f)));
  o.geometric = true;
  o.outside_masks_tracker_only = true;
  DualBBoxFilter with_evidence(o);
  with_evidence.setIntrinsics(CameraIntrinsics{30, 30, 20, 15, 40, 30});
  with_evidence.setDynamicEvidence(evidence);
  with_evidence.filter(scene.depth, detections({person(14, 9, 26, 26)}));
  const auto dynamic = with_evidence.filter(scene.depth, detections({}));
  EXPECT_EQ(cv::countNonZero(dynamic.static_depth(body)), 0);
  EXPECT_EQ(cv::countNonZero(dynamic.kept_for_map_only(body)), 0);
}

// outside_masks_tracker_only with a mask: the box rule's depth beside the mask (the floor at the
// person's feet, at their depth) goes to the map; the masked body stays removed.
TEST(DualBBoxFilter, OutsideMasksTrackerOnlyKeepsTheBoxRuleBesideAMask) {
  Scene scene;
  const cv::Rect floor(22, 22, 4, 4);
  scene.depth(floor).setTo(1.55f);
  const PersonDetection p = upperBodyMasked();
  DualBBoxFilter::Options o = maskOptions();
  const auto paper = DualBBoxFilter(o).filter(scene.depth, detections({p}));
  EXPECT_EQ(cv::countNonZero(paper.static_depth(floor)), 0);  // the box rule took the floor
  o.outside_masks_tracker_only = true;
  const auto r = DualBBoxFilter(o).filter(scene.depth, detections({p}));
  EXPECT_EQ(cv::countNonZero(r.static_depth(floor)), floor.area());
  ASSERT_FALSE(r.kept_for_map_only.empty());
  EXPECT_EQ(cv::countNonZero(r.kept_for_map_only(floor)), floor.area());
  EXPECT_EQ(cv::countNonZero(r.static_depth(cv::Rect(15, 10, 6, 12))), 0);  // the masked body
  EXPECT_EQ(r.people.size(), 1u);
}

TEST(DualBBoxFilter, TemporalGuardWidensWithThePersonsMotionAtTheirDepth) {
  // A person 0.6 m from a still camera (fx = 60), cols 30..39, rows 20..49, in front of a wall at
  // 3 m; next frame they moved 8 px to the right and the detector missed them.
  cv::Mat before(60, 80, CV_32F, cv::Scalar(3.0f)), after = before.clone();
  before(cv::Rect(30, 20, 10, 30)).setTo(0.6f);
  after(cv::Rect(38, 20, 10, 30)).setTo(0.6f);
  DualBBoxFilter::Options o = testOptions();
  o.temporal = true;
  o.temporal_guard.dilation = 2;
  auto keptOfThePerson = [&](double person_motion) {
    o.temporal_guard.person_motion = person_motion;
    DualBBoxFilter filter(o);
    filter.setIntrinsics(CameraIntrinsics{60, 60, 40, 30, 80, 60});
    filter.filter(before, detections({person(30, 20, 40, 50)}));
    const auto r = filter.filter(after, detections({}));
    EXPECT_EQ(cv::countNonZero(r.removed), cv::countNonZero(r.removed(cv::Rect(38, 20, 10, 30))))
        << "only the person's pixels are removed, the wall stays";
    return cv::countNonZero(r.static_depth(cv::Rect(38, 20, 10, 30)));
  };
  // Pixels only: the guard (half-resolution cells 15..19 dilated by 1 cell: cols 28..41) covers 4
  // of the person's 10 new columns.
  EXPECT_EQ(keptOfThePerson(0.0), 6 * 30);
  // 0.1 m at 0.6 m is 5 cells (10 px): the whole person is guarded.
  EXPECT_EQ(keptOfThePerson(0.1), 0);
}

// temporal_guard.static_tolerance: a surface beside a person, at their depth, that the previous
// frame gave to the map (a chair) is guarded for the tracker but spared for the map; a missed
// person who moves brings new surfaces and stays removed for both.
TEST(DualBBoxFilter, TemporalGuardSparesForTheMapASurfaceThatWasThereBefore) {
  // Wall at 3 m, a person at 1.5 m (cols 30..39, rows 20..49), a chair at 1.55 m beside their
  // legs (cols 42..45, rows 38..49): outside the box's ring, inside the guard's 6 px.
  cv::Mat scene(60, 80, CV_32F, cv::Scalar(3.0f));
  scene(cv::Rect(30, 20, 10, 30)).setTo(1.5f);
  const cv::Rect chair(42, 38, 4, 12);
  scene(chair).setTo(1.55f);
  DualBBoxFilter::Options o = testOptions();
  o.temporal = true;
  auto twoFrames = [&](double static_tolerance) {
    o.temporal_guard.static_tolerance = static_tolerance;
    DualBBoxFilter filter(o);
    filter.setIntrinsics(CameraIntrinsics{60, 60, 40, 30, 80, 60});
    const auto first = filter.filter(scene, detections({person(30, 20, 40, 50)}));
    EXPECT_EQ(cv::countNonZero(first.static_depth(chair)), chair.area()) << "nothing carried yet";
    return filter.filter(scene, detections({person(30, 20, 40, 50)}));
  };
  const auto paper = twoFrames(0.0);
  EXPECT_EQ(cv::countNonZero(paper.static_depth(chair)), 0) << "the guard takes the chair";
  const auto spared = twoFrames(0.05);
  EXPECT_EQ(cv::countNonZero(spared.static_depth(chair)), chair.area());
  EXPECT_EQ(cv::countNonZero(spared.removed(chair)), 0);
  ASSERT_FALSE(spared.kept_for_map_only.empty());
  EXPECT_EQ(cv::countNonZero(spared.kept_for_map_only), chair.area()) << "the tracker still leaves it out";
  EXPECT_EQ(cv::countNonZero(spared.static_depth(cv::Rect(30, 20, 10, 30))), 0) << "the person stays removed";

  // The person, missed from the second frame on, walks 2 px a frame to the right (no chair).
  cv::Mat wall(60, 80, CV_32F, cv::Scalar(3.0f));
  o.temporal_guard.static_tolerance = 0.05;
  DualBBoxFilter filter(o);
  filter.setIntrinsics(CameraIntrinsics{60, 60, 40, 30, 80, 60});
  cv::Mat walking = wall.clone();
  walking(cv::Rect(30, 20, 10, 30)).setTo(1.5f);
  filter.filter(walking, detections({person(30, 20, 40, 50)}));
  for (int frame = 1; frame <= 3; ++frame) {
    const cv::Rect body(30 + 2 * frame, 20, 10, 30);
    walking = wall.clone();
    walking(body).setTo(1.5f);
    const auto r = filter.filter(walking, detections({}));
    EXPECT_EQ(cv::countNonZero(r.static_depth(body)), 0) << "frame " << frame;
    EXPECT_TRUE(r.kept_for_map_only.empty() || cv::countNonZero(r.kept_for_map_only) == 0) << "frame " << frame;
  }
}

// The floor at a person's feet: inside the box, at the person's depth, but far from their mask.
// The box rule removes it; with mask_box_reach it acts only near the mask and the floor is kept,
// the person (mask and the box pixels next to it) still removed.
TEST(DualBBoxFilter, MaskReachKeepsBoxPixelsFarFromThePerson) {
  Scene scene;
  scene.depth(cv::Rect(22, 22, 4, 4)).setTo(1.55f);  // "floor" in the box's corner at the body's depth
  const PersonDetection p = upperBodyMasked();
  DualBBoxFilter::Options o = maskOptions();
  const auto everywhere = DualBBoxFilter(o).filter(scene.depth, detections({p}));
  EXPECT_EQ(everywhere.static_depth.at<float>(24, 24), 0.f);  // the paper: removed
  o.mask_box_reach = 2;
  const auto near_mask = DualBBoxFilter(o).filter(scene.depth, detections({p}));
  EXPECT_EQ(near_mask.static_depth.at<float>(24, 24), 1.55f);  // 3+ pixels from the mask: kept
  EXPECT_EQ(near_mask.static_depth.at<float>(23, 20), 0.f);    // body 2 pixels below the mask: removed
  EXPECT_EQ(near_mask.static_depth.at<float>(15, 18), 0.f);    // the masked body
  EXPECT_EQ(near_mask.static_depth.at<float>(27, 20), 2.5f);   // the ring rule is bounded too
  EXPECT_EQ(everywhere.static_depth.at<float>(27, 20), 0.f);
}

// The depth gate: what the ring rule removed next to the mask but far from the person's depth is
// given back; the arm at the person's depth and the body outside the mask stay removed.
TEST(DualBBoxFilter, DepthGateGivesBackDepthApartFromThePerson) {
  const Scene scene;
  const PersonDetection p = upperBodyMasked();
  DualBBoxFilter::Options o = maskOptions();
  const auto ungated = DualBBoxFilter(o).filter(scene.depth, detections({p}));
  o.depth_gate = PersonDepthGate::Options{8, 0.1};
  const auto gated = DualBBoxFilter(o).filter(scene.depth, detections({p}));
  EXPECT_EQ(ungated.static_depth.at<float>(27, 20), 0.f);   // the ring rule took it
  EXPECT_EQ(gated.static_depth.at<float>(27, 20), 2.5f);    // 1 m behind the person 6 rows above
  EXPECT_EQ(gated.static_depth.at<float>(12, 13), 0.f);     // the arm, 0.08 m from the body
  EXPECT_EQ(gated.static_depth.at<float>(23, 20), 0.f);     // the body below the mask
  EXPECT_EQ(gated.static_depth.at<float>(15, 18), 0.f);     // the masked body
  EXPECT_EQ(differing(gated.static_depth(cv::Rect(0, 0, 40, 26)), ungated.static_depth(cv::Rect(0, 0, 40, 26))), 0);
}

TEST(DualBBoxFilter, GeometricAdditionUsesTheEvidence) {
  const Scene scene;
  auto evidence = std::make_shared<PredictedDepthEvidence>(0.15);
  evidence->setPrediction(cv::Mat(30, 40, CV_32F, cv::Scalar(3.02f)));  // the wall everywhere
  DualBBoxFilter::Options o = testOptions();
  o.geometric = true;
  DualBBoxFilter filter(o);
  filter.setDynamicEvidence(evidence);
  const auto r = filter.filter(scene.depth, detections({}));  // no box at all
  // Everything in front of the wall by > 0.15 m is dynamic: the person, both arms, the 2.5 m and
  // the 1.9 m pixels; the 3.12 m object is behind the prediction and stays.
  cv::Mat expected = scene.depth.clone();
  expected.setTo(0.f, scene.depth < 3.02f - 0.15f);
  EXPECT_EQ(differing(r.static_depth, expected), 0);
  EXPECT_EQ(r.static_depth.at<float>(8, 20), 3.12f);
}

// A person the detector missed, seen as a candidate region (cols 10..19, rows 5..24 at 2 m before
// a 3 m wall). The prediction already holds the lower half of them (they reached a keyframe), so
// the evidence alone finds only the upper half; with the candidate the whole person goes, and
// stays gone for candidate_memory frames once the evidence is lost entirely.
TEST(DualBBoxFilter, GeometricEvidenceConfirmsACandidateAndCarriesIt) {
  cv::Mat depth(30, 40, CV_32F, cv::Scalar(3.0f));
  const cv::Rect body(10, 5, 10, 20);
  depth(body).setTo(2.0f);
  cv::Mat prediction(30, 40, CV_32F, cv::Scalar(3.0f));
  prediction(cv::Rect(10, 15, 10, 10)).setTo(2.0f);
  PersonDetection candidate;
  candidate.mask = cv::Mat::zeros(30, 40, CV_8U);
  candidate.mask(body).setTo(255);
  Detections seen;
  seen.candidates = {candidate};
  auto evidence = std::make_shared<PredictedDepthEvidence>(0.15);
  DualBBoxFilter::Options o = testOptions();
  o.geometric = true;
  o.mask_dilation = 0;
  o.geometric_addition.candidate_memory = 2;
  auto removedOnBody = [&](DualBBoxFilter& filter) {
    return cv::countNonZero(filter.filter(depth, seen).removed(body));
  };

  o.geometric_addition.candidate_min_dynamic = 0.0;  // candidates ignored: the evidence's half only
  DualBBoxFilter evidence_only(o);
  evidence_only.setDynamicEvidence(evidence);
  evidence->setPrediction(prediction);
  EXPECT_EQ(removedOnBody(evidence_only), 100);

  o.geometric_addition.candidate_min_dynamic = 0.3;
  DualBBoxFilter fused(o);
  fused.setDynamicEvidence(evidence);
  EXPECT_EQ(removedOnBody(fused), 200);
  const cv::Mat all_static = depth.clone();  // the person wholly in the prediction now
  evidence->setPrediction(all_static);
  EXPECT_EQ(removedOnBody(fused), 200);  // carried, 1 frame without evidence
  EXPECT_EQ(removedOnBody(fused), 200);  // 2
  EXPECT_EQ(removedOnBody(fused), 0);    // memory spent

  // Too little evidence (a tenth of the region, under 0.3): no person, only the evidence's pixels go.
  cv::Mat little = depth.clone();
  little(cv::Rect(10, 23, 10, 2)).setTo(3.0f);
  evidence->setPrediction(little);
  DualBBoxFilter fresh(o);
  fresh.setDynamicEvidence(evidence);
  EXPECT_EQ(removedOnBody(fresh), 20);
}

// candidate_min_score: a candidate the detector is sure of (its mean mask probability) and that
// stands in front of its surroundings is a person even where the prediction shows it as static (a
// person present since the first keyframe); one it is less sure of still needs evidence.
TEST(DualBBoxFilter, SureCandidateNeedsNoEvidence) {
  cv::Mat depth(30, 40, CV_32F, cv::Scalar(3.0f));
  const cv::Rect body(10, 5, 10, 20);
  depth(body).setTo(2.0f);
  PersonDetection candidate;
  candidate.mask = cv::Mat::zeros(30, 40, CV_8U);
  candidate.mask(body).setTo(255);
  auto evidence = std::make_shared<PredictedDepthEvidence>(0.15);
  evidence->setPrediction(depth.clone());  // everything static to the prediction
  DualBBoxFilter::Options o = testOptions();
  o.geometric = true;
  o.mask_dilation = 0;
  o.geometric_addition.candidate_min_score = 0.95;
  auto removedOnBody = [&](float score) {
    candidate.score = score;
    Detections seen;
    seen.candidates = {candidate};
    DualBBoxFilter filter(o);
    filter.setDynamicEvidence(evidence);
    return cv::countNonZero(filter.filter(depth, seen).removed(body));
  };
  EXPECT_EQ(removedOnBody(0.97f), 200);  // 1 m in front of the wall around it
  EXPECT_EQ(removedOnBody(0.93f), 0);
  // Flush with the wall (0.1 m in front, under candidate_min_front = 0.2): the selfie model's false
  // components on plain or blurred walls look like this.
  depth(body).setTo(2.9f);
  evidence->setPrediction(depth.clone());
  EXPECT_EQ(removedOnBody(0.97f), 0);
  o.geometric_addition.candidate_min_front = 0.0;  // no such test
  EXPECT_EQ(removedOnBody(0.97f), 200);
  o.geometric_addition.candidate_min_score = 0.0;  // off: evidence always needed
  EXPECT_EQ(removedOnBody(0.97f), 0);
}

// keep_static: where the prediction knows the depth as static, what only the ring (or box, or
// temporal) rule removed is given back; a person's mask is never given back.
TEST(DualBBoxFilter, KeepStaticGivesBackWhatOnlyTheRulesRemoved) {
  const Scene scene;
  PersonDetection p = person(14, 9, 26, 26);
  p.mask = cv::Mat::zeros(30, 40, CV_8U);
  p.mask(cv::Rect(15, 10, 10, 15)).setTo(255);  // the whole person
  auto evidence = std::make_shared<PredictedDepthEvidence>(0.15);
  evidence->setPrediction(scene.depth.clone());  // every measured depth was seen before
  evidence->setStaticMargin(0.05);
  DualBBoxFilter::Options o = testOptions();
  o.use_mask = true;
  o.mask_dilation = 0;
  o.geometric = true;
  DualBBoxFilter rules_only(o);
  rules_only.setDynamicEvidence(evidence);
  const auto before = rules_only.filter(scene.depth, detections({p}));
  EXPECT_EQ(before.static_depth.at<float>(27, 20), 0.f);  // ring outlier removed (line 11)
  EXPECT_EQ(before.static_depth.at<float>(12, 13), 0.f);
  o.geometric_addition.keep_static = true;
  DualBBoxFilter keeping(o);
  keeping.setDynamicEvidence(evidence);
  const auto after = keeping.filter(scene.depth, detections({p}));
  EXPECT_EQ(after.static_depth.at<float>(27, 20), 2.5f);  // known static: kept
  EXPECT_EQ(after.static_depth.at<float>(12, 13), 1.6f);
  EXPECT_EQ(cv::countNonZero(after.static_depth(cv::Rect(15, 10, 10, 15))), 0);  // the masked person
  // Where the prediction has no depth, the rules stand.
  cv::Mat partial = scene.depth.clone();
  partial.at<float>(27, 20) = 0.f;
  evidence->setPrediction(partial);
  EXPECT_EQ(keeping.filter(scene.depth, detections({p})).static_depth.at<float>(27, 20), 0.f);
}

// A camera 0.5 m above a level floor, looking level (camera y down: the floor is the plane
// y = 0.5, Hyperplane((0, -1, 0), 0.5) like pf2_slam's floorInCamera), 40x30 pixels at f = 30: the
// floor fills rows 19..29 (3.3 m at row 19 to 1.03 m at row 29), a wall at 3.5 m the rows above,
// and a person stands at 0.9 m in cols 15..24, rows 5..29.
struct FloorScene {
  CameraIntrinsics k{30, 30, 19.5, 14.5, 40, 30};
  Eigen::Hyperplane<double, 3> floor_c{Eigen::Vector3d(0, -1, 0), 0.5};
  cv::Rect body{15, 5, 10, 25};
  cv::Mat depth = cv::Mat(30, 40, CV_32F, cv::Scalar(3.5f));
  FloorScene() {
    for (int v = 19; v < 30; ++v) depth.row(v).setTo(static_cast<float>(0.5 * k.fy / (v - k.cy)));
    depth(body).setTo(0.9f);
  }
};

// The static plane: the floor's pixels are known static without any prediction (no keyframe saw
// them), the person standing on it and the wall are not; through the filter, the floor a box rule
// took around a person (no mask) is given back, the person stays removed.
TEST(PredictedDepthEvidence, TheFloorPlaneIsStaticWhatStandsOnItIsNot) {
  const FloorScene scene;
  PredictedDepthEvidence evidence(0.15);
  evidence.setPlaneMargin(0.03);
  EXPECT_TRUE(evidence.staticMask(scene.depth).empty());  // no plane: no opinion
  evidence.setStaticPlane(scene.floor_c, scene.k);
  const cv::Mat known = evidence.staticMask(scene.depth);
  ASSERT_FALSE(known.empty());
  EXPECT_EQ(cv::countNonZero(known), 11 * 30);  // the floor's rows beside the person
  EXPECT_EQ(cv::countNonZero(known(scene.body)), 0);
  EXPECT_EQ(cv::countNonZero(known.rowRange(0, 19)), 0);  // the wall
  evidence.setPlaneMargin(0.0);
  EXPECT_TRUE(evidence.staticMask(scene.depth).empty());  // margin 0: off
  CameraIntrinsics other = scene.k;
  other.width = 80;
  evidence.setPlaneMargin(0.03);
  evidence.setStaticPlane(scene.floor_c, other);
  EXPECT_THROW(evidence.staticMask(scene.depth), Error);

  auto shared = std::make_shared<PredictedDepthEvidence>(0.15);
  shared->setPlaneMargin(0.03);
  DualBBoxFilter::Options o = testOptions();
  o.geometric = true;
  o.geometric_addition.keep_static = true;
  DualBBoxFilter filter(o);
  filter.setDynamicEvidence(shared);
  const Detections seen = detections({person(12, 4, 27, 29)});
  const cv::Mat floor_removed = filter.filter(scene.depth, seen).removed & known;
  // The ring's three columns (11, 27, 28) on the 11 floor rows, and the box's five columns beside
  // the person on rows 25..29, where the floor (1.03-1.43 m) lies in the person's interval.
  EXPECT_EQ(cv::countNonZero(floor_removed), 3 * 11 + 5 * 5);
  shared->setStaticPlane(scene.floor_c, scene.k);
  const DualBBoxFilter::Result kept = filter.filter(scene.depth, seen);
  EXPECT_EQ(cv::countNonZero(kept.removed & known), 0);
  EXPECT_EQ(cv::countNonZero(kept.removed(scene.body)), scene.body.area());
}

// Without the geometric addition (no residual against a prediction), an evidence given to the
// filter still confirms the candidates the detector is sure of and its static opinion (here the
// floor plane alone) still gives back what a box rule took; its dynamic opinion is not used: a
// candidate it alone would confirm stays, as does depth in front of the prediction.
TEST(DualBBoxFilter, WithoutTheGeometricAdditionSureCandidatesAndTheFloorStillCount) {
  const FloorScene scene;
  auto evidence = std::make_shared<PredictedDepthEvidence>(0.15);
  evidence->setPlaneMargin(0.03);
  evidence->setStaticPlane(scene.floor_c, scene.k);
  evidence->setPrediction(cv::Mat(30, 40, CV_32F, cv::Scalar(3.5f)));  // the wall everywhere
  DualBBoxFilter::Options o = testOptions();
  o.geometric = false;
  o.mask_dilation = 0;
  o.geometric_addition.keep_static = true;
  o.geometric_addition.candidate_min_score = 0.95;
  PersonDetection candidate;
  candidate.mask = cv::Mat::zeros(30, 40, CV_8U);
  candidate.mask(scene.body).setTo(255);
  auto removedOnBody = [&](float score, bool geometric) {
    candidate.score = score;
    Detections seen;
    seen.candidates = {candidate};
    o.geometric = geometric;
    DualBBoxFilter filter(o);
    filter.setDynamicEvidence(evidence);
    return cv::countNonZero(filter.filter(scene.depth, seen).removed(scene.body));
  };
  EXPECT_EQ(removedOnBody(0.97f, false), scene.body.area());  // sure: 2.6 m in front of the wall
  EXPECT_EQ(removedOnBody(0.5f, false), 0);  // only the residual would confirm it
  EXPECT_EQ(removedOnBody(0.5f, true), scene.body.area());

  o.geometric = false;
  DualBBoxFilter filter(o);
  filter.setDynamicEvidence(evidence);
  const Detections seen = detections({person(12, 4, 27, 29)});
  const DualBBoxFilter::Result kept = filter.filter(scene.depth, seen);
  const cv::Mat floor = evidence->staticMask(scene.depth);
  EXPECT_EQ(cv::countNonZero(floor), 11 * 30);
  EXPECT_EQ(cv::countNonZero(kept.removed & floor), 0);  // 3 * 11 + 5 * 5 with no plane (above)
  EXPECT_EQ(cv::countNonZero(kept.removed(scene.body)), scene.body.area());
  filter.setDynamicEvidence(nullptr);  // no evidence: the box rules alone
  EXPECT_EQ(cv::countNonZero(filter.filter(scene.depth, seen).removed & floor), 3 * 11 + 5 * 5);
}

// keep_static_behind_masks: the known static depth under a person's mask that lies behind their
// interval by more than human_margin (the wall the mask's edge spills over) is kept and reported;
// the person's own depth under the mask stays removed, known static or not.
// One masked person through a filter with the static evidence of `prediction` (margin 0.05 m),
// keep_static on and keep_static_behind_masks as given.
DualBBoxFilter::Result filterWithPrediction(const cv::Mat& depth, const PersonDetection& p, const cv::Mat& prediction,
                                            int mask_dilation, bool keep_behind) {
  auto evidence = std::make_shared<PredictedDepthEvidence>(0.15);
  evidence->setPrediction(prediction);
  evidence->setStaticMargin(0.05);
  DualBBoxFilter::Options o = testOptions();
  o.use_mask = true;
  o.mask_dilation = mask_dilation;
  o.geometric = true;
  o.geometric_addition.keep_static = true;
  o.keep_static_behind_masks = keep_behind;
  DualBBoxFilter filter(o);
  filter.setDynamicEvidence(evidence);
  return filter.filter(depth, detections({p}));
}

TEST(DualBBoxFilter, KeepStaticBehindMasksKeepsTheWallUnderTheMaskAndReportsIt) {
  const Scene scene;
  PersonDetection p = person(14, 9, 26, 26);
  p.mask = cv::Mat::zeros(30, 40, CV_8U);
  p.mask(cv::Rect(15, 10, 10, 15)).setTo(255);  // holds the 1.9 m pixel at row 20, col 16 too
  cv::Mat prediction = scene.depth.clone();
  auto run = [&](bool keep_behind) { return filterWithPrediction(scene.depth, p, prediction, 0, keep_behind); };
  const auto off = run(false);
  EXPECT_EQ(off.static_depth.at<float>(20, 16), 0.f);  // under the mask: removed
  EXPECT_TRUE(off.kept_for_map_only.empty());
  const auto on = run(true);
  EXPECT_EQ(on.static_depth.at<float>(20, 16), 1.9f);
  EXPECT_EQ(on.removed.at<uint8_t>(20, 16), 0);
  ASSERT_FALSE(on.kept_for_map_only.empty());
  EXPECT_EQ(cv::countNonZero(on.kept_for_map_only), 1);
  EXPECT_EQ(on.kept_for_map_only.at<uint8_t>(20, 16), 255);
  EXPECT_EQ(cv::countNonZero(on.static_depth(cv::Rect(15, 10, 10, 15))), 1);  // the person stays removed
  EXPECT_EQ(on.people.size(), off.people.size());
  // Not known static (no prediction there): the mask stands.
  prediction.at<float>(20, 16) = 0.f;
  EXPECT_EQ(run(true).static_depth.at<float>(20, 16), 0.f);
}

// keep_static_behind_masks, the dilation's ring: known static depth the mask's dilation took around
// the segmenter's own mask is kept and reported even at the person's depth (a chair beside them);
// the person's outline the segmenter missed is in front of the prediction, so it stays removed, and
// so does the person's depth under their own mask that the prediction holds.
TEST(DualBBoxFilter, KeepStaticBehindMasksKeepsTheKnownStaticRingOfTheDilation) {
  Scene scene;
  const cv::Rect chair(25, 15, 1, 6);  // beside the person, at their depth
  scene.depth(chair).setTo(1.55f);
  PersonDetection p = person(14, 9, 26, 26);
  p.mask = cv::Mat::zeros(30, 40, CV_8U);
  p.mask(cv::Rect(16, 10, 9, 15)).setTo(255);  // misses the person's column 15
  cv::Mat prediction = scene.depth.clone();
  prediction(cv::Rect(15, 10, 10, 15)).setTo(3.02f);  // the wall behind the person...
  prediction.at<float>(12, 20) = 1.52f;               // ... but one pixel of them stood still
  auto run = [&](bool keep) { return filterWithPrediction(scene.depth, p, prediction, 1, keep); };
  const auto off = run(false);
  EXPECT_EQ(cv::countNonZero(off.static_depth(chair)), 0);
  const auto on = run(true);
  EXPECT_EQ(cv::countNonZero(on.static_depth(chair)), chair.area());
  ASSERT_FALSE(on.kept_for_map_only.empty());
  EXPECT_EQ(cv::countNonZero(on.kept_for_map_only(chair)), chair.area());
  EXPECT_EQ(cv::countNonZero(on.static_depth(cv::Rect(15, 10, 1, 15))), 0);  // the missed outline
  EXPECT_EQ(on.static_depth.at<float>(12, 20), 0.f);                          // under the own mask
  EXPECT_EQ(on.removed.at<uint8_t>(12, 20), 255);
}

// keep_static and a person the pose network found without a mask: what their box rule labelled on
// their skeleton stays removed even where the prediction knows it as static (a person in view
// since the first keyframe); the rest of the box is given back as for any box.
TEST(DualBBoxFilter, KeepStaticLeavesAPosedPersonsSkeletonRemoved) {
  const Scene scene;
  PersonDetection p = person(14, 9, 26, 26);  // no mask
  auto evidence = std::make_shared<PredictedDepthEvidence>(0.15);
  evidence->setPrediction(scene.depth.clone());
  evidence->setStaticMargin(0.05);
  DualBBoxFilter::Options o = testOptions();
  o.use_mask = true;
  o.geometric = true;
  o.geometric_addition.keep_static = true;
  auto run = [&](const PersonDetection& detection) {
    DualBBoxFilter filter(o);
    filter.setDynamicEvidence(evidence);
    return filter.filter(scene.depth, detections({detection}));
  };
  const cv::Rect body(15, 10, 10, 15);
  EXPECT_EQ(cv::countNonZero(run(p).static_depth(body)), 149);  // no pose: all given back (one pixel has no depth)
  // COCO-17: nose, shoulders, hips, knees and ankles on the body (eyes, ears, arms unseen).
  p.keypoints.assign(17, Keypoint2d{0, 0, 0});
  const std::vector<std::pair<int, cv::Point>> seen = {{0, {19, 10}},  {5, {16, 12}},  {6, {23, 12}},
                                                       {11, {16, 19}}, {12, {23, 19}}, {13, {16, 22}},
                                                       {14, {23, 22}}, {15, {16, 24}}, {16, {23, 24}}};
  for (const auto& [index, at] : seen) p.keypoints[index] = Keypoint2d{float(at.x), float(at.y), 0.9f};
  const auto posed = run(p);
  EXPECT_EQ(posed.static_depth.at<float>(15, 19), 0.f);  // the torso
  EXPECT_EQ(posed.static_depth.at<float>(23, 16), 0.f);  // a shin
  EXPECT_EQ(posed.static_depth.at<float>(23, 20), 1.52f);  // between the legs, off the skeleton
  EXPECT_EQ(posed.static_depth.at<float>(27, 20), 2.5f);   // the ring's outlier, known static
  const int kept = cv::countNonZero(posed.static_depth(body));
  EXPECT_GT(kept, 0);
  EXPECT_LT(kept, 75);  // most of the body is on the skeleton
  // Too few confident keypoints (under joint_min_count): no pose, all given back.
  for (Keypoint2d& k : p.keypoints) k.score = 0.1f;
  p.keypoints[5].score = p.keypoints[6].score = 0.9f;
  EXPECT_EQ(cv::countNonZero(run(p).static_depth(body)), 149);
}

// The temporal addition moves pixels with the camera's intrinsics: none given, or of another
// size than the depth, is an error, not a silent default camera.
TEST(DualBBoxFilter, TemporalAdditionNeedsTheFramesIntrinsics) {
  const Scene scene;
  DualBBoxFilter::Options o = testOptions();
  o.temporal = true;
  DualBBoxFilter filter(o);
  EXPECT_THROW(filter.filter(scene.depth, detections({person(14, 9, 26, 26)})), Error);
  filter.setIntrinsics(CameraIntrinsics{30, 30, 20, 15, 64, 48});
  EXPECT_THROW(filter.filter(scene.depth, detections({person(14, 9, 26, 26)})), Error);
  filter.setIntrinsics(CameraIntrinsics{30, 30, 20, 15, 40, 30});
  EXPECT_NO_THROW(filter.filter(scene.depth, detections({person(14, 9, 26, 26)})));
}

TEST(WarpDepth, IdentityAndTranslation) {
  cv::Mat depth = cv::Mat::zeros(30, 40, CV_32F);
  depth.at<float>(15, 20) = 2.f;
  const CameraIntrinsics K{30, 30, 20, 15, 40, 30};
  EXPECT_EQ(differing(warpDepth(depth, K, Eigen::Isometry3d::Identity()), depth), 0);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0.2, 0, 1.0);  // point (0, 0, 2) -> (0.2, 0, 3): u = 20 + 2
  const cv::Mat moved = warpDepth(depth, K, T);
  EXPECT_FLOAT_EQ(moved.at<float>(15, 22), 3.f);
  EXPECT_EQ(cv::countNonZero(moved), 1);
}

}  // namespace
}  // namespace pf2
