#include "pf2/registration/rgbd_odometry.h"

#include <sys/stat.h>

#include <cmath>
#include <atomic>
#include <random>
#include <thread>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/core/pose.h"
#include "pf2/io/tum_sequence.h"
#include "rendered_scene.h"

namespace pf2 {
namespace {

CameraIntrinsics camera() { return CameraIntrinsics::tumFreiburg1(); }

double translationError(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return (a.inverse() * b).translation().norm();
}
double rotationErrorDeg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return rotationAngle((a.inverse() * b).rotation()) * 180.0 / M_PI;
}

class RenderedPair : public testing::Test {
 protected:
  void SetUp() override {
    T_w_ref = test::cameraPose(0.1, -0.1, -0.5, 0.05, 0.1, 0.0);
    T_w_cur = test::cameraPose(0.125, -0.09, -0.48, 0.06, 0.125, 0.01);
    ref = test::renderRoom(T_w_ref, camera(), 0);
    cur = test::renderRoom(T_w_cur, camera(), 1);
    T_ref_cur_true = T_w_ref.inverse() * T_w_cur;
  }
  Eigen::Isometry3d T_w_ref, T_w_cur, T_ref_cur_true;
  Frame ref, cur;
};

TEST_F(RenderedPair, DenseRecoversKnownMotion) {
  RgbdOdometry odometry;
  OdometryFrame a = odometry.prepare(ref), b = odometry.prepare(cur);
  odometry.makeReference(&a);
  const DenseAlignment result = odometry.refine(a, b, Eigen::Isometry3d::Identity());
  EXPECT_TRUE(result.valid);
  EXPECT_LT(translationError(result.T_ref_cur, T_ref_cur_true), 0.001);
  EXPECT_LT(rotationErrorDeg(result.T_ref_cur, T_ref_cur_true), 0.05);
  EXPECT_GT(result.inlier_ratio, 0.8);
  EXPECT_LT(result.geometric_rmse, 0.002);
}

// The normal equations are summed over the samples in parallel (OpenCV's thread pool, which the
// pipeline's other threads use at the same time): the result must not depend on which thread
// summed which part, so a run with a synchronous back end and map repeats to the byte. Two
// callers at once make the pool split the work differently from call to call.
TEST_F(RenderedPair, DenseResultIsTheSameOnEveryCall) {
  RgbdOdometry odometry;
  OdometryFrame a = odometry.prepare(ref), b = odometry.prepare(cur);
  odometry.makeReference(&a);
  const DenseAlignment first = odometry.refine(a, b, Eigen::Isometry3d::Identity());
  ASSERT_GT(first.sampled_points, 4000);  // several parts to sum, at the finest level at least
  std::atomic<int> differing{0};
  const auto repeat = [&] {
    for (int call = 0; call < 40; ++call) {
      const DenseAlignment again = odometry.refine(a, b, Eigen::Isometry3d::Identity());
      if (!(again.T_ref_cur.matrix() == first.T_ref_cur.matrix())) ++differing;
    }
  };
  std::thread other(repeat);
  repeat();
  other.join();
  EXPECT_EQ(differing.load(), 0);
}

TEST_F(RenderedPair, SparseRansacGivesCoarsePoseAndEstimateRefinesIt) {
  RgbdOdometry odometry;
  OdometryFrame a = odometry.prepare(ref), b = odometry.prepare(cur);
  odometry.makeReference(&a);
  odometry.featureAligner().extract(&b);
  EXPECT_GT(a.keypoints.size(), 100u);
  const SparseAlignment sparse = odometry.featureAligner().align(a, b);
  ASSERT_TRUE(sparse.valid);
  EXPECT_LT(translationError(sparse.T_ref_cur, T_ref_cur_true), 0.01);
  EXPECT_LT(rotationErrorDeg(sparse.T_ref_cur, T_ref_cur_true), 0.5);

  const OdometryResult result = odometry.estimateWithoutPrior(a, &b);
  ASSERT_TRUE(result.valid);
  EXPECT_LT(translationError(result.T_ref_cur, T_ref_cur_true), 0.001);
  EXPECT_LT(rotationErrorDeg(result.T_ref_cur, T_ref_cur_true), 0.05);
}

TEST_F(RenderedPair, LargeMotionFallsBackToFeatures) {
  // 25 cm and 12 degrees: beyond what the dense pyramid converges from identity.
  T_w_cur = test::cameraPose(0.35, -0.05, -0.3, 0.1, 0.3, 0.05);
  cur = test::renderRoom(T_w_cur, camera(), 1);
  T_ref_cur_true = T_w_ref.inverse() * T_w_cur;
  RgbdOdometry odometry;
  OdometryFrame a = odometry.prepare(ref), b = odometry.prepare(cur);
  odometry.makeReference(&a);
  const OdometryResult result = odometry.estimate(a, &b, Eigen::Isometry3d::Identity());
  EXPECT_TRUE(result.used_features);
  ASSERT_TRUE(result.valid);
  EXPECT_LT(translationError(result.T_ref_cur, T_ref_cur_true), 0.001);
  EXPECT_LT(rotationErrorDeg(result.T_ref_cur, T_ref_cur_true), 0.05);
}

TEST_F(RenderedPair, PersonMaskKeepsAMovingOccluderOut) {
  // A "person" close to the camera in the current frame only, textured and at the wrong depth.
  cv::Mat mask(cur.depth.size(), CV_8U, cv::Scalar(0));
  const cv::Rect person(200, 60, 180, 400);
  mask(person).setTo(255);
  cur.depth(person).setTo(0.9f);
  cv::randu(cur.rgb(person), cv::Scalar::all(0), cv::Scalar::all(255));
  RgbdOdometry odometry;
  OdometryFrame a = odometry.prepare(ref), b = odometry.prepare(cur, mask);
  odometry.makeReference(&a);
  EXPECT_EQ(cv::countNonZero(b.levels[0].depth(person)), 0);
  const OdometryResult result = odometry.estimate(a, &b, Eigen::Isometry3d::Identity());
  ASSERT_TRUE(result.valid);
  EXPECT_LT(translationError(result.T_ref_cur, T_ref_cur_true), 0.001);
  EXPECT_LT(rotationErrorDeg(result.T_ref_cur, T_ref_cur_true), 0.05);
}

TEST_F(RenderedPair, PreparingLeavesTheCallersPersonMaskAsItWas) {
  cv::Mat mask(cur.depth.size(), CV_8U, cv::Scalar(0));
  mask(cv::Rect(200, 60, 180, 400)).setTo(255);
  const cv::Mat before = mask.clone();
  RgbdOdometry::Options options;
  options.person_mask_dilation = 6;
  const OdometryFrame frame = RgbdOdometry(options).prepare(cur, mask);
  // The frame leaves the dilated mask out (6 px beside the rectangle), the caller keeps its own.
  EXPECT_EQ(frame.levels[0].depth.at<float>(260, 200 - 6 + 1), 0.f);
  EXPECT_EQ(cv::countNonZero(mask != before), 0);
}

// A person nobody removed, 0.75 m from the camera in the reference and 0.70 m in the current
// frame (a step towards it), in front of a room 2-4 m away. Under the z^2 noise model all the way
// down, their points would weigh 10-30 times the room's each and pull the pose along.
TEST_F(RenderedPair, NearPointsWeighNoMoreThanAtTheFloorDepth) {
  const cv::Rect person(200, 60, 180, 400);
  ref.depth(person).setTo(0.75f);
  cur.depth(person).setTo(0.70f);
  ref.rgb(person).setTo(cv::Scalar::all(128));  // plain clothes: only the depth term sees them
  cur.rgb(person).setTo(cv::Scalar::all(128));
  auto translationErrorWith = [&](double floor_depth) {
    RgbdOdometry::Options options;
    options.depth_sigma_floor_depth = floor_depth;
    RgbdOdometry odometry(options);
    OdometryFrame a = odometry.prepare(ref), b = odometry.prepare(cur);
    odometry.makeReference(&a);
    return translationError(odometry.estimate(a, &b, Eigen::Isometry3d::Identity()).T_ref_cur, T_ref_cur_true);
  };
  const double z_squared = translationErrorWith(0.0), floored = translationErrorWith(1.0);
  std::printf("unremoved near person: translation error %.2f mm (z^2 model), %.2f mm (floor at 1 m)\n",
              1000 * z_squared, 1000 * floored);
  EXPECT_LT(floored, 0.6 * z_squared);
}

TEST_F(RenderedPair, UnusableFramesAreNotValid) {
  RgbdOdometry odometry;
  OdometryFrame a = odometry.prepare(ref);
  odometry.makeReference(&a);
  Frame empty = cur;
  empty.depth.setTo(0.0f);
  OdometryFrame b = odometry.prepare(empty);
  EXPECT_EQ(b.valid_depth_pixels, 0);
  EXPECT_FALSE(odometry.estimate(a, &b, Eigen::Isometry3d::Identity()).valid);

  Frame noise = cur;
  cv::randu(noise.depth, cv::Scalar(0.5), cv::Scalar(4.0));
  cv::randu(noise.rgb, cv::Scalar::all(0), cv::Scalar::all(255));
  OdometryFrame c = odometry.prepare(noise);
  const OdometryResult result = odometry.estimate(a, &c, Eigen::Isometry3d::Identity());
  EXPECT_FALSE(result.valid);
  EXPECT_LT(result.dense.inlier_ratio, odometry.options().min_inlier_ratio);
}

TEST(RgbdOdometry, RejectsMalformedInput) {
  RgbdOdometry odometry;
  Frame frame;
  frame.rgb = cv::Mat(48, 64, CV_8UC3, cv::Scalar::all(0));
  frame.depth = cv::Mat(48, 64, CV_16U, cv::Scalar(0));
  EXPECT_THROW(odometry.prepare(frame), Error);
  frame.depth = cv::Mat(48, 64, CV_32F, cv::Scalar(1));
  EXPECT_THROW(odometry.prepare(frame, cv::Mat(10, 10, CV_8U)), Error);
  RgbdOdometry::Options bad;
  bad.finest_level = 3;
  EXPECT_THROW(RgbdOdometry{bad}, Error);
}

// Real frames: consecutive TUM fr1/desk frames against the motion-capture ground truth.
TEST(RgbdOdometry, RealTumDeskConsecutiveFrames) {
  const std::string folder = std::string(PF2_SHARED_DATA) + "/tum_fr1_desk_9";
  struct stat info;
  if (::stat((folder + "/rgb.txt").c_str(), &info) != 0) GTEST_SKIP() << "no " << folder;
  TumSequence sequence(folder);
  const Trajectory truth = sequence.groundTruth();
  RgbdOdometry::Options options;
  options.distortion = kTumFreiburg1Distortion;
  RgbdOdometry odometry(options);
  OdometryFrame previous = odometry.prepare(sequence.frame(0));
  odometry.makeReference(&previous);
  double worst_t = 0.0, worst_r = 0.0;
  for (size_t i = 1; i < sequence.size(); ++i) {
    OdometryFrame current = odometry.prepare(sequence.frame(i));
    Eigen::Isometry3d T_w_a, T_w_b;
    ASSERT_TRUE(interpolateAt(truth, sequence.timestamp(i - 1), 0.1, &T_w_a));
    ASSERT_TRUE(interpolateAt(truth, sequence.timestamp(i), 0.1, &T_w_b));
    const OdometryResult result =
        odometry.estimate(previous, &current, Eigen::Isometry3d::Identity());
    EXPECT_TRUE(result.valid) << "frame " << i;
    const Eigen::Isometry3d expected = T_w_a.inverse() * T_w_b;
    worst_t = std::max(worst_t, translationError(result.T_ref_cur, expected));
    worst_r = std::max(worst_r, rotationErrorDeg(result.T_ref_cur, expected));
    odometry.makeReference(&current);
    previous = std::move(current);
  }
  // fr1/desk moves 1-1.7 cm and ~1.3 deg per frame; its depth is taken ~14 ms after the colour
  // image (0.5 deg of motion), so colour and depth disagree by about that much.
  EXPECT_LT(worst_t, 0.008);
  EXPECT_LT(worst_r, 0.6);
  std::printf("fr1_desk_9 consecutive: worst %.4f m, %.3f deg\n", worst_t, worst_r);
}

}  // namespace
}  // namespace pf2
