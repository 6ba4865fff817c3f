#include "pf2/slam/removal_backfill.h"

#include <vector>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

CameraIntrinsics smallCamera() {
  CameraIntrinsics k;
  k.fx = k.fy = 200.0;
  k.cx = 160.0;
  k.cy = 120.0;
  k.width = 320;
  k.height = 240;
  return k;
}

// A wall 3 m ahead (world z = 3) and a person: a flat patch at world z = 2 spanning
// x in [person_x, person_x + 0.4] and y in [-0.3, 0.3]; the camera at world x = camera_x looking
// along +z. Depth in metres; *person (optional) gets 255 on the person's pixels.
cv::Mat render(double camera_x, double person_x, cv::Mat* person = nullptr) {
  const CameraIntrinsics k = smallCamera();
  cv::Mat depth(k.height, k.width, CV_32F, cv::Scalar(3.f));
  if (person) *person = cv::Mat::zeros(depth.size(), CV_8U);
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const double x = camera_x + 2.0 * (u - k.cx) / k.fx, y = 2.0 * (v - k.cy) / k.fy;
      if (x >= person_x && x <= person_x + 0.4 && y >= -0.3 && y <= 0.3) {
        depth.at<float>(v, u) = 2.f;
        if (person) person->at<uint8_t>(v, u) = 255;
      }
    }
  }
  return depth;
}

Eigen::Isometry3d cameraAt(double x) {
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  T_w_c.translation().x() = x;
  return T_w_c;
}

// What a released frame looked like, and how much of the person / the wall it lost.
struct Released {
  int index = -1;
  int person_removed = 0, person_pixels = 0, wall_removed = 0;
};

class Backfill : public testing::Test {
 protected:
  // A frame of a camera at camera_x with the person at person_x, nothing removed yet.
  RemovalBackfill::Frame frame(int index, double camera_x, double person_x) {
    RemovalBackfill::Frame f;
    cv::Mat person;
    f.depth = render(camera_x, person_x, &person);
    f.removed = cv::Mat::zeros(f.depth.size(), CV_8U);
    f.T_w_c = cameraAt(camera_x);
    f.intrinsics = smallCamera();
    f.release = [this, index, person](const RemovalBackfill::Frame& done) {
      Released r;
      r.index = index;
      r.person_pixels = cv::countNonZero(person);
      r.person_removed = cv::countNonZero(done.removed & person);
      r.wall_removed = cv::countNonZero(done.removed & ~person);
      EXPECT_EQ(cv::countNonZero((done.depth > 0.f) & done.removed), 0);  // removed depth is gone
      released.push_back(r);
    };
    return f;
  }
  // The points of the person as found in a frame of a camera at camera_x.
  RemovalBackfill::Points personFound(const RemovalBackfill& backfill, double camera_x, double person_x) {
    cv::Mat person;
    cv::Mat people_depth = render(camera_x, person_x, &person);
    people_depth.setTo(0.f, person == 0);
    return backfill.personPoints(people_depth, smallCamera(), cameraAt(camera_x), std::nullopt);
  }
  std::vector<Released> released;
};

TEST_F(Backfill, APersonFoundLateIsRemovedFromTheFramesWhereTheyStoodAlready) {
  RemovalBackfill backfill;  // waits 30 frames
  for (int i = 0; i < 5; ++i) backfill.push(frame(i, 0.05 * i, 0.0), {});  // missed by the detector
  EXPECT_TRUE(released.empty());
  backfill.push(frame(5, 0.25, 0.0), personFound(backfill, 0.25, 0.0));
  backfill.flush();
  ASSERT_EQ(released.size(), 6u);
  for (int i = 0; i < 5; ++i) {
    const Released& r = released[i];
    EXPECT_EQ(r.index, i);
    ASSERT_GT(r.person_pixels, 2000);
    // Every second pixel and row carried, the gaps closed: all of the person.
    EXPECT_GE(r.person_removed, 0.98 * r.person_pixels) << "frame " << i;
    // The wall loses at most the closing disc's ring around them (2 px).
    EXPECT_LT(r.wall_removed, 0.3 * r.person_pixels) << "frame " << i;
  }
}

TEST_F(Backfill, APersonWhoMovedSinceRemovesNothingBefore) {
  RemovalBackfill backfill;
  // Before: the person stood 0.6 m to the right; where they are found later, the frames before saw
  // the wall 1 m behind them.
  for (int i = 0; i < 5; ++i) backfill.push(frame(i, 0.0, 0.6), {});
  backfill.push(frame(5, 0.0, 0.0), personFound(backfill, 0.0, 0.0));
  backfill.flush();
  ASSERT_EQ(released.size(), 6u);
  for (const Released& r : released) {
    EXPECT_EQ(r.person_removed, 0) << r.index;
    EXPECT_EQ(r.wall_removed, 0) << r.index;
  }
}

TEST_F(Backfill, FramesLeaveInOrderAfterTheirWaitAndNotAtAllWithoutOne) {
  RemovalBackfill::Options options;
  options.frames = 3;
  RemovalBackfill backfill(options);
  for (int i = 0; i < 5; ++i) {
    backfill.push(frame(i, 0.0, 0.0), {});
    EXPECT_EQ(backfill.waiting(), static_cast<size_t>(std::min(i + 1, 3)));
  }
  ASSERT_EQ(released.size(), 2u);
  EXPECT_EQ(released[0].index, 0);
  EXPECT_EQ(released[1].index, 1);
  backfill.flush();
  ASSERT_EQ(released.size(), 5u);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(released[i].index, i);

  options.frames = 0;  // off: each frame leaves as it comes, unchanged
  RemovalBackfill off(options);
  released.clear();
  off.push(frame(0, 0.0, 0.0), {});
  off.push(frame(1, 0.0, 0.0), personFound(off, 0.0, 0.0));
  ASSERT_EQ(released.size(), 2u);
  EXPECT_EQ(released[0].person_removed, 0);
}

TEST_F(Backfill, PointsNearTheFloorAreNotCarried) {
  RemovalBackfill backfill;
  cv::Mat person;
  cv::Mat people_depth = render(0.0, 0.0, &person);
  people_depth.setTo(0.f, person == 0);
  const RemovalBackfill::Points all = backfill.personPoints(people_depth, smallCamera(), cameraAt(0.0), std::nullopt);
  // The floor at y = 0.3 (image y points down): up = -y, the floor's height along it -0.3.
  const std::pair<Eigen::Vector3d, double> floor{Eigen::Vector3d(0.0, -1.0, 0.0), -0.3};
  const RemovalBackfill::Points above = backfill.personPoints(people_depth, smallCamera(), cameraAt(0.0), floor);
  ASSERT_FALSE(all.empty());
  int expected = 0;
  for (const Eigen::Vector3f& p : all) expected += (0.3 - p.y() >= 0.1) ? 1 : 0;
  EXPECT_EQ(static_cast<int>(above.size()), expected);
  EXPECT_LT(above.size(), all.size());
  for (const Eigen::Vector3f& p : above) EXPECT_GE(0.3 - p.y(), 0.1 - 1e-5);
}

TEST(RemovalBackfillOptions, OutOfRangeOptionsAndMalformedFramesAreRefused) {
  RemovalBackfill::Options bad;
  bad.frames = 301;
  EXPECT_THROW(RemovalBackfill{bad}, Error);
  bad = RemovalBackfill::Options();
  bad.tolerance = 0.0;
  EXPECT_THROW(RemovalBackfill{bad}, Error);
  bad = RemovalBackfill::Options();
  bad.floor_clearance = -0.1;
  EXPECT_THROW(RemovalBackfill{bad}, Error);

  RemovalBackfill backfill;
  RemovalBackfill::Frame frame;
  frame.depth = cv::Mat::zeros(4, 4, CV_16U);
  frame.removed = cv::Mat::zeros(4, 4, CV_8U);
  EXPECT_THROW(backfill.push(frame, {}), Error);
  frame.depth = cv::Mat::zeros(4, 4, CV_32F);
  frame.removed = cv::Mat::zeros(4, 5, CV_8U);
  EXPECT_THROW(backfill.push(frame, {}), Error);
}

}  // namespace
}  // namespace pf2
