#include "pf2/registration/tracker.h"

#include <cmath>

#include <gtest/gtest.h>

#include "pf2/core/pose.h"
#include "rendered_scene.h"

namespace pf2 {
namespace {

// Small images keep the rendering cheap; the odometry is resolution independent.
CameraIntrinsics smallCamera() { return CameraIntrinsics::tumFreiburg1().scaled(0.5); }

Eigen::Isometry3d pathPose(int i) {
  return test::cameraPose(0.01 * i, -0.1 + 0.004 * i, -0.5 + 0.006 * i, 0.02, 0.012 * i, 0.0);
}

Tracker::Options syncOptions() {
  Tracker::Options options;
  options.asynchronous_backend = false;
  return options;
}

// Without bridging a frame that cannot be measured is lost at once (the tests of relocalisation).
Tracker::Options unbridgedOptions() {
  Tracker::Options options = syncOptions();
  options.max_bridged_frames = 0;
  return options;
}

TEST(Tracker, TracksARenderedPathAndReportsLostFrames) {
  Tracker tracker(unbridgedOptions());
  const CameraIntrinsics k = smallCamera();
  const Eigen::Isometry3d T_w_0 = pathPose(0);
  auto expected = [&](int i) { return T_w_0.inverse() * pathPose(i); };  // world = first camera

  for (int i = 0; i < 6; ++i) {
    const TrackResult r = tracker.track(test::renderRoom(pathPose(i), k, i));
    ASSERT_EQ(r.status, TrackStatus::kOk) << "frame " << i;
    EXPECT_LT((r.T_w_c.translation() - expected(i).translation()).norm(), 0.002) << "frame " << i;
    EXPECT_EQ(r.keyframe_created, i == 0) << "frame " << i;  // small motion: one keyframe
    EXPECT_FALSE(r.stage_ms.empty());
  }

  // A frame without depth (e.g. a person covering the whole view, removed from depth).
  Frame blank = test::renderRoom(pathPose(6), k, 6);
  blank.depth.setTo(0.0f);
  EXPECT_EQ(tracker.track(blank).status, TrackStatus::kLost);

  // A frame of noise: depth and colour random.
  Frame noise = test::renderRoom(pathPose(7), k, 7);
  cv::randu(noise.depth, cv::Scalar(0.3), cv::Scalar(5.0));
  cv::randu(noise.rgb, cv::Scalar::all(0), cv::Scalar::all(255));
  const TrackResult lost = tracker.track(noise);
  EXPECT_EQ(lost.status, TrackStatus::kLost);
  EXPECT_FALSE(lost.odometry.valid);

  // Back to the scene, 3 cm further along: relocalised against the keyframes, then tracked.
  const TrackResult back = tracker.track(test::renderRoom(pathPose(9), k, 9));
  ASSERT_EQ(back.status, TrackStatus::kRelocalised);
  EXPECT_LT((back.T_w_c.translation() - expected(9).translation()).norm(), 0.002);
  EXPECT_LT(rotationAngle((back.T_w_c.inverse() * expected(9)).rotation()), 0.001);
  const TrackResult next = tracker.track(test::renderRoom(pathPose(10), k, 10));
  EXPECT_EQ(next.status, TrackStatus::kOk);
  EXPECT_LT((next.T_w_c.translation() - expected(10).translation()).norm(), 0.002);

  EXPECT_GT(tracker.stats().summary("odometry").count, 0);
  EXPECT_GT(tracker.stats().summary("relocalise").count, 0);
}

TEST(Tracker, NoPoseBeforeTheFirstUsableFrame) {
  Tracker tracker(syncOptions());
  Frame blank = test::renderRoom(pathPose(0), smallCamera(), 0);
  blank.depth.setTo(0.0f);
  EXPECT_EQ(tracker.track(blank).status, TrackStatus::kLost);
  EXPECT_EQ(tracker.keyframes().size(), 0u);
  const TrackResult first = tracker.track(test::renderRoom(pathPose(1), smallCamera(), 1));
  EXPECT_EQ(first.status, TrackStatus::kOk);
  EXPECT_TRUE(first.keyframe_created);
  EXPECT_LT(first.T_w_c.translation().norm(), 1e-12);  // the world frame is this camera
}

// A person covering most of the view leaves a sliver of static depth: below
// min_tracking_depth_fraction the frame gets no pose; above it but below
// min_keyframe_depth_fraction it is tracked but never becomes a keyframe, even when the selector
// asks for one (keyframes are made on every frame here).
TEST(Tracker, ASliverOfDepthGivesNoPoseAndNoKeyframe) {
  Tracker::Options options = unbridgedOptions();
  options.keyframes.max_translation = 0.001;
  Tracker tracker(options);
  for (int i = 0; i < 3; ++i)
    ASSERT_TRUE(tracker.track(test::renderRoom(pathPose(i), smallCamera(), i)).keyframe_created);

  Frame band = test::renderRoom(pathPose(3), smallCamera(), 3);
  band.depth.rowRange(0, band.depth.rows * 6 / 7).setTo(0.0f);  // 14 % left
  const TrackResult r = tracker.track(band);
  ASSERT_EQ(r.status, TrackStatus::kOk);
  EXPECT_FALSE(r.keyframe_created);
  EXPECT_EQ(tracker.keyframes().size(), 3u);
  const Eigen::Isometry3d expected = pathPose(0).inverse() * pathPose(3);
  EXPECT_LT((r.T_w_c.translation() - expected.translation()).norm(), 0.01);

  Frame sliver = test::renderRoom(pathPose(4), smallCamera(), 4);
  sliver.depth.rowRange(sliver.depth.rows / 25, sliver.depth.rows).setTo(0.0f);  // 4 % left
  EXPECT_EQ(tracker.track(sliver).status, TrackStatus::kLost);
  EXPECT_EQ(tracker.keyframes().size(), 3u);

  const TrackResult clear = tracker.track(test::renderRoom(pathPose(5), smallCamera(), 5));
  ASSERT_NE(clear.status, TrackStatus::kLost);
  EXPECT_TRUE(clear.keyframe_created);
}

// Without a motion prior a relocalisation is trusted only with more overlap than tracking needs,
// or when the keyframe aligned back onto the frame agrees (the back end's two-way rule). A view
// turned 0.6 rad from the only keyframe (inlier ratio about 0.45) stays lost by overlap alone and
// is relocalised, to the right pose, by the two-way rule; one turned 0.3 rad (about 0.7) is
// relocalised by overlap. A frame of noise is never relocalised.
TEST(Tracker, RelocalisationNeedsMoreOverlapThanTrackingOrTwoWayAgreement) {
  const Eigen::Isometry3d far = pathPose(0) * test::cameraPose(0, 0, 0, 0, 0.6, 0);
  const Eigen::Isometry3d near = pathPose(0) * test::cameraPose(0, 0, 0, 0, 0.3, 0);
  // Tracks the first view, loses a frame of noise, then tries `view`; returns that result.
  auto relocalise = [](const Tracker::Options& options, const Eigen::Isometry3d& view) {
    Tracker tracker(options);
    EXPECT_EQ(tracker.track(test::renderRoom(pathPose(0), smallCamera(), 0)).status, TrackStatus::kOk);
    Frame noise = test::renderRoom(pathPose(1), smallCamera(), 1);
    cv::randu(noise.depth, cv::Scalar(0.3), cv::Scalar(5.0));
    cv::randu(noise.rgb, cv::Scalar::all(0), cv::Scalar::all(255));
    EXPECT_EQ(tracker.track(noise).status, TrackStatus::kLost);
    return tracker.track(test::renderRoom(view, smallCamera(), 2));
  };
  Tracker::Options overlap_only = unbridgedOptions();
  overlap_only.backend.min_local_agreement = 1.01;  // no two-way rule
  const TrackResult weak = relocalise(overlap_only, far);
  EXPECT_EQ(weak.status, TrackStatus::kLost);
  EXPECT_GT(weak.odometry.dense.inlier_ratio, 0.0);  // it was tried and aligned, with little overlap
  EXPECT_LT(weak.odometry.dense.inlier_ratio, overlap_only.min_relocalisation_inlier_ratio);

  const TrackResult two_way = relocalise(unbridgedOptions(), far);
  ASSERT_EQ(two_way.status, TrackStatus::kRelocalised);
  EXPECT_LT(two_way.odometry.dense.inlier_ratio, overlap_only.min_relocalisation_inlier_ratio);
  EXPECT_LT((two_way.T_w_c.translation() - (pathPose(0).inverse() * far).translation()).norm(), 0.005);

  const TrackResult back = relocalise(overlap_only, near);
  ASSERT_EQ(back.status, TrackStatus::kRelocalised);
  const Eigen::Isometry3d expected = pathPose(0).inverse() * near;
  EXPECT_LT((back.T_w_c.translation() - expected.translation()).norm(), 0.005);
}

// Frames that cannot be measured (no depth, then noise) right after tracked ones are bridged with
// the motion prior's pose, at most max_bridged_frames in a row, and never become keyframes; the
// next frame of the scene is measured again against the same keyframe.
TEST(Tracker, BridgesAShortGapWithTheMotionPrior) {
  Tracker::Options options = syncOptions();
  options.max_bridged_frames = 2;
  Tracker tracker(options);
  const CameraIntrinsics k = smallCamera();
  auto expected = [&](int i) { return pathPose(0).inverse() * pathPose(i); };
  for (int i = 0; i < 4; ++i) ASSERT_EQ(tracker.track(test::renderRoom(pathPose(i), k, i)).status, TrackStatus::kOk);

  Frame blank = test::renderRoom(pathPose(4), k, 4);
  blank.depth.setTo(0.0f);
  const TrackResult bridged = tracker.track(blank);
  ASSERT_EQ(bridged.status, TrackStatus::kBridged);
  EXPECT_TRUE(hasPose(bridged.status));
  EXPECT_FALSE(bridged.keyframe_created);
  // Constant velocity (faded by bridge_motion_decay) from frame 3: about 1 cm from the truth.
  EXPECT_LT((bridged.T_w_c.translation() - expected(4).translation()).norm(), 0.02);
  Frame noise = test::renderRoom(pathPose(5), k, 5);
  cv::randu(noise.depth, cv::Scalar(0.3), cv::Scalar(5.0));
  cv::randu(noise.rgb, cv::Scalar::all(0), cv::Scalar::all(255));
  EXPECT_EQ(tracker.track(noise).status, TrackStatus::kBridged);
  EXPECT_EQ(tracker.track(blank).status, TrackStatus::kLost);  // the third in a row
  EXPECT_EQ(tracker.keyframes().size(), 1u);

  const TrackResult back = tracker.track(test::renderRoom(pathPose(7), k, 7));
  ASSERT_TRUE(hasPose(back.status));
  EXPECT_LT((back.T_w_c.translation() - expected(7).translation()).norm(), 0.003);
}

// While frames are bridged, the last measured frame stays the frame-to-frame fallback: the camera
// turns on (0.16 rad a frame, no new keyframe allowed), a frame without depth is bridged, and the
// next view, too far turned to align to the keyframe, is measured against the last measured frame
// instead of waiting for relocalisation (switched off here).
TEST(Tracker, AfterABridgedFrameTheLastMeasuredFrameIsStillTheFallback) {
  Tracker::Options options = syncOptions();
  options.max_keyframe_condition = 0;              // no frame after the first becomes a keyframe
  options.min_relocalisation_inlier_ratio = 1.01;  // relocalisation off: by overlap ...
  options.backend.min_local_agreement = 1.01;      // ... and by two-way agreement
  Tracker tracker(options);
  const CameraIntrinsics k = smallCamera();
  auto pose = [](int i) { return test::cameraPose(0, 0, -0.5, 0, 0.16 * i, 0); };
  auto frameAt = [&](int i) {
    Frame frame = test::renderRoom(pose(i), k, i);
    frame.timestamp = 0.1 * i;
    return frame;
  };
  for (int i = 0; i < 4; ++i) ASSERT_EQ(tracker.track(frameAt(i)).status, TrackStatus::kOk) << "frame " << i;
  ASSERT_EQ(tracker.keyframes().size(), 1u);
  Frame blank = frameAt(4);
  blank.depth.setTo(0.0f);
  ASSERT_EQ(tracker.track(blank).status, TrackStatus::kBridged);

  const TrackResult back = tracker.track(frameAt(5));
  EXPECT_EQ(back.status, TrackStatus::kOk);
  EXPECT_LT((back.T_w_c.translation() - (pose(0).inverse() * pose(5)).translation()).norm(), 0.005);
  EXPECT_LT(rotationAngle((back.T_w_c.rotation().transpose() * (pose(0).inverse() * pose(5)).rotation())), 0.01);
}

// The divergence guard: an odometry pose that jumps farther than max_speed allows since the last
// measured frame is rejected, and the frame is bridged instead of taking it. (Only relocalisation,
// a match without any prior verified by overlap or two-way agreement, may place a frame that far;
// it is switched off here.)
TEST(Tracker, RejectsAnImpossibleJump) {
  Tracker::Options options = syncOptions();
  options.max_speed = 0.3;  // m/s: 1 cm per 1/30 s frame, plus the 4 cm tolerance
  options.min_relocalisation_inlier_ratio = 1.01;  // relocalisation off: by overlap ...
  options.backend.min_local_agreement = 1.01;      // ... and by two-way agreement
  Tracker tracker(options);
  const CameraIntrinsics k = smallCamera();
  for (int i = 0; i < 3; ++i) {
    Frame frame = test::renderRoom(pathPose(i), k, i);
    frame.timestamp = i / 30.0;
    ASSERT_EQ(tracker.track(frame).status, TrackStatus::kOk);
  }
  // The camera "jumps" 12 cm in one frame: the odometry measures it, the guard refuses it.
  Frame jump = test::renderRoom(pathPose(2) * test::cameraPose(0.12, 0, 0, 0, 0, 0), k, 3);
  jump.timestamp = 3 / 30.0;
  const TrackResult r = tracker.track(jump);
  EXPECT_EQ(r.status, TrackStatus::kBridged);
  EXPECT_LT((r.T_w_c.translation() - (pathPose(0).inverse() * pathPose(2)).translation()).norm(), 0.03);
}

TEST(Tracker, KeyframesFollowMotion) {
  Tracker::Options options = syncOptions();
  options.keyframes.max_translation = 0.03;
  Tracker tracker(options);
  int created = 0;
  for (int i = 0; i < 8; ++i) {
    const TrackResult r = tracker.track(test::renderRoom(pathPose(i), smallCamera(), i));
    ASSERT_NE(r.status, TrackStatus::kLost);
    created += r.keyframe_created;
  }
  // 8 frames, 1.2 cm each -> about 8.4 cm: the first keyframe plus one every ~3 cm.
  EXPECT_GE(created, 3);
  EXPECT_LE(created, 4);
  EXPECT_EQ(static_cast<int>(tracker.keyframes().size()), created);
}

}  // namespace
}  // namespace pf2
