#include "pf2/registration/reference_cleaner.h"

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/registration/rgbd_odometry.h"

namespace pf2 {
namespace {

// 80x60 frames of a wall at 3 m; `with_person` adds a block at 1.5 m (cols 30..49, rows 20..39).
Frame wallFrame(bool with_person) {
  Frame frame;
  frame.intrinsics = CameraIntrinsics::tumFreiburg3().scaled(0.125);
  frame.rgb = cv::Mat(60, 80, CV_8UC3, cv::Scalar(90, 120, 150));
  frame.depth = cv::Mat(60, 80, CV_32F, cv::Scalar(3.0f));
  if (with_person) frame.depth(cv::Rect(30, 20, 20, 20)).setTo(1.5f);
  return frame;
}

int validDepth(const OdometryFrame& frame, int level) { return cv::countNonZero(frame.levels[level].depth); }

// The person was in the keyframe and has walked off: the later frame sees the wall through where
// they stood. After `votes` such frames the block is gone from every level; the wall stays.
TEST(ReferenceCleaner, RemovesWhatLaterFramesSeeThrough) {
  const RgbdOdometry odometry;
  OdometryFrame reference = odometry.prepare(wallFrame(true));
  const OdometryFrame later = odometry.prepare(wallFrame(false));
  const int before = validDepth(reference, 0);
  ReferenceCleaner cleaner;  // 2 votes, stride 2
  EXPECT_EQ(cleaner.update(&reference, later, Eigen::Isometry3d::Identity()), 0);  // one vote
  EXPECT_EQ(validDepth(reference, 0), before);
  // The block's pixels on the stride-2 grid whose 3x3 neighbourhood in the later frame is all wall.
  EXPECT_EQ(cleaner.update(&reference, later, Eigen::Isometry3d::Identity()), 100);
  EXPECT_EQ(validDepth(reference, 0), before - 400);
  EXPECT_EQ(reference.levels[0].depth.at<float>(30, 40), 0.0f);
  EXPECT_EQ(reference.levels[0].depth.at<float>(10, 10), 3.0f);
  EXPECT_EQ(reference.levels[1].depth.at<float>(15, 20), 0.0f);  // coarser levels follow
  EXPECT_GT(reference.levels[1].depth.at<float>(5, 5), 0.0f);
}

// The same scene seen again, or a static foreground one pixel off at its edge: nothing goes.
TEST(ReferenceCleaner, KeepsWhatIsStillThere) {
  const RgbdOdometry odometry;
  OdometryFrame reference = odometry.prepare(wallFrame(true));
  Frame shifted = wallFrame(false);
  shifted.depth(cv::Rect(31, 20, 20, 20)).setTo(1.5f);  // the block one pixel to the right
  const OdometryFrame later = odometry.prepare(shifted);
  const OdometryFrame same = odometry.prepare(wallFrame(true));
  ReferenceCleaner cleaner;
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(cleaner.update(&reference, same, Eigen::Isometry3d::Identity()), 0);
    EXPECT_EQ(cleaner.update(&reference, later, Eigen::Isometry3d::Identity()), 0);
  }
  ReferenceCleaner::Options off;
  off.enabled = false;
  ReferenceCleaner disabled(off);
  const OdometryFrame gone = odometry.prepare(wallFrame(false));
  for (int i = 0; i < 3; ++i) EXPECT_EQ(disabled.update(&reference, gone, Eigen::Isometry3d::Identity()), 0);
  ReferenceCleaner::Options bad;
  bad.votes = 0;
  EXPECT_THROW(ReferenceCleaner{bad}, Error);
}

}  // namespace
}  // namespace pf2
