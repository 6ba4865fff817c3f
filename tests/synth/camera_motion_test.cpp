#include "pf2/synth/camera_motion.h"

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/core/pose.h"

namespace pf2 {
namespace {

TEST(CameraMotion, NamesRoundTripAndUnknownNamesThrow) {
  for (const char* name : {"static", "xyz", "halfsphere", "rpy", "loop", "above"}) {
    EXPECT_STREQ(cameraMotionName(cameraMotionFromName(name)), name);
  }
  EXPECT_THROW(cameraMotionFromName("circle"), Error);
}

TEST(CameraMotion, XyzTranslatesWithoutRotatingAndRpyRotatesInPlace) {
  const Eigen::Isometry3d start = cameraPoseAt(CameraMotion::kXyz, 0.0, 12.0);
  double max_translation = 0.0, max_rotation = 0.0;
  for (double t = 0.0; t < 12.0; t += 0.1) {
    const Eigen::Isometry3d xyz = cameraPoseAt(CameraMotion::kXyz, t, 12.0);
    max_translation = std::max(max_translation, (xyz.translation() - start.translation()).norm());
    EXPECT_NEAR(rotationAngle(start.linear().transpose() * xyz.linear()), 0.0, 1e-9);
    const Eigen::Isometry3d rpy = cameraPoseAt(CameraMotion::kRpy, t, 12.0);
    EXPECT_NEAR((rpy.translation() - start.translation()).norm(), 0.0, 1e-9);
    max_rotation = std::max(max_rotation, rotationAngle(start.linear().transpose() * rpy.linear()));
  }
  EXPECT_NEAR(max_translation, 0.25, 0.01);
  EXPECT_NEAR(max_rotation, 20.0 * M_PI / 180.0, 0.01);
}

TEST(CameraMotion, LoopReturnsToItsStartAndTravelsFar) {
  const double duration = 20.0;
  const Eigen::Isometry3d start = cameraPoseAt(CameraMotion::kLoop, 0.0, duration);
  const Eigen::Isometry3d end = cameraPoseAt(CameraMotion::kLoop, duration, duration);
  EXPECT_LT((end.translation() - start.translation()).norm(), 1e-6);
  EXPECT_LT(rotationAngle(start.linear().transpose() * end.linear()), 1e-6);
  double length = 0.0;
  for (double t = 0.0; t < duration; t += 0.05) {
    length += (cameraPoseAt(CameraMotion::kLoop, t + 0.05, duration).translation() -
               cameraPoseAt(CameraMotion::kLoop, t, duration).translation()).norm();
  }
  EXPECT_GT(length, 6.0);
}

TEST(CameraMotion, AboveLooksDownAtTheFloorFromHigh) {
  for (double t = 0.0; t < 15.0; t += 0.5) {
    const Eigen::Isometry3d T_w_c = cameraPoseAt(CameraMotion::kAbove, t, 15.0);
    EXPECT_NEAR(T_w_c.translation().z(), 2.4, 1e-9);
    // The optical axis points 35-50 degrees below the horizon.
    const double down = std::asin(-T_w_c.linear().col(2).z()) * 180.0 / M_PI;
    EXPECT_GT(down, 35.0) << t;
    EXPECT_LT(down, 50.0) << t;
  }
}

TEST(CameraMotion, EveryMotionIsSmoothAndLooksIntoTheRoom) {
  for (const auto motion : {CameraMotion::kStatic, CameraMotion::kXyz, CameraMotion::kHalfsphere,
                            CameraMotion::kRpy, CameraMotion::kLoop, CameraMotion::kAbove}) {
    for (double t = 0.0; t < 15.0; t += 1.0 / 30.0) {
      const Eigen::Isometry3d a = cameraPoseAt(motion, t, 15.0);
      const Eigen::Isometry3d b = cameraPoseAt(motion, t + 1.0 / 30.0, 15.0);
      // Hand-held speeds: under 3 cm and 3 degrees per frame.
      ASSERT_LT((b.translation() - a.translation()).norm(), 0.03) << cameraMotionName(motion) << " " << t;
      ASSERT_LT(rotationAngle(a.linear().transpose() * b.linear()), 0.05) << cameraMotionName(motion) << " " << t;
      // The optical axis points into the room (+y) and the camera stays inside it.
      ASSERT_GT(a.linear().col(2).y(), 0.5);
      ASSERT_GT(a.translation().y(), 0.3);
      ASSERT_LT(a.translation().y(), 1.5);
    }
  }
}

}  // namespace
}  // namespace pf2
