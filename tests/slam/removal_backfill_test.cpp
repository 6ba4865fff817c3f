#include "pf2/slam/removal_backfill.h"

#include <cmath>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

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
  // The person's pixels at least RemovalBackfill::kOutline inside their outline (what is carried).
  int inside_removed = 0, inside_pixels = 0;
  cv::Mat removed, person;  // CV_8U as released; the person's pixels
};

// `person` (CV_8U) without the outline personPoints leaves out.
cv::Mat insideOutline(const cv::Mat& person) {
  const int size = 2 * RemovalBackfill::kOutline + 1;
  cv::Mat inside;
  cv::erode(person, inside, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size, size)));
  return inside;
}

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
      const cv::Mat inside = insideOutline(person);
      r.inside_pixels = cv::countNonZero(inside);
      r.inside_removed = cv::countNonZero(done.removed & inside);
      r.removed = done.removed.clone();
      r.person = person;
      EXPECT_EQ(cv::countNonZero((done.depth > 0.f) & done.removed), 0);  // removed depth is gone
      released.push_back(r);
    };
    return f;
  }
  // The same frame as the filter leaves it: the person removed with `spill` pixels of the wall
  // around them (0: nothing removed), the depth as measured kept aside.
  RemovalBackfill::Frame filtered(int index, double camera_x, double person_x, int spill) {
    RemovalBackfill::Frame f = frame(index, camera_x, person_x);
    f.measured = f.depth.clone();
    if (spill > 0) {
      cv::Mat person;
      render(camera_x, person_x, &person);
      cv::dilate(person, f.removed, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * spill + 1, 2 * spill + 1)));
      f.depth.setTo(0.f, f.removed);
    }
    return f;
  }
  // The points of the person as found in a frame of a camera at camera_x.
  RemovalBackfill::Points personFound(const RemovalBackfill& backfill, double camera_x, double person_x) {
    return backfill.personPoints(personDepth(camera_x, person_x), smallCamera(), cameraAt(camera_x), std::nullopt);
  }
  // The person's depth alone (0 elsewhere) as a camera at camera_x sees them; *person (optional)
  // gets 255 on their pixels.
  static cv::Mat personDepth(double camera_x, double person_x, cv::Mat* person = nullptr) {
    cv::Mat mask;
    cv::Mat people_depth = render(camera_x, person_x, &mask);
    people_depth.setTo(0.f, mask == 0);
    if (person) *person = mask;
    return people_depth;
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
    // Every third pixel and row carried, the gaps closed: all of the person but their outline.
    EXPECT_GE(r.inside_removed, 0.98 * r.inside_pixels) << "frame " << i;
    EXPECT_GE(r.person_removed, 0.85 * r.person_pixels) << "frame " << i;
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

TEST_F(Backfill, APersonFoundEarlierWhoStaysIsRemovedFromTheFramesAfterThatMissThem) {
  RemovalBackfill backfill;  // carries a frame's people into the 30 frames after it too
  backfill.push(frame(0, 0.0, 0.0), personFound(backfill, 0.0, 0.0));
  for (int i = 1; i < 6; ++i) backfill.push(frame(i, 0.05 * i, 0.0), {});  // missed by the detector
  backfill.flush();
  ASSERT_EQ(released.size(), 6u);
  for (int i = 1; i < 6; ++i) {
    const Released& r = released[i];
    ASSERT_GT(r.person_pixels, 2000);
    EXPECT_GE(r.inside_removed, 0.98 * r.inside_pixels) << "frame " << i;
    EXPECT_GE(r.person_removed, 0.85 * r.person_pixels) << "frame " << i;
    EXPECT_LT(r.wall_removed, 0.3 * r.person_pixels) << "frame " << i;
  }
}

TEST_F(Backfill, APersonWhoMovedOnRemovesNothingAfterAndNothingIsCarriedPastTheWait) {
  RemovalBackfill::Options options;
  options.frames = 3;
  RemovalBackfill backfill(options);
  // Found in frame 0, then gone 0.6 m to the right: where they stood, the frames after see the wall.
  backfill.push(frame(0, 0.0, 0.0), personFound(backfill, 0.0, 0.0));
  for (int i = 1; i < 4; ++i) backfill.push(frame(i, 0.0, 0.6), {});
  // Found in frame 4, then standing still, missed: carried into the three frames after it only.
  backfill.push(frame(4, 0.0, 0.0), personFound(backfill, 0.0, 0.0));
  for (int i = 5; i < 10; ++i) backfill.push(frame(i, 0.0, 0.0), {});
  backfill.flush();
  ASSERT_EQ(released.size(), 10u);
  for (int i = 1; i < 10; ++i) {
    const Released& r = released[i];
    if (i >= 5 && i <= 7) {
      EXPECT_GE(r.inside_removed, 0.98 * r.inside_pixels) << "frame " << i;
      EXPECT_LT(r.wall_removed, 0.3 * r.person_pixels) << "frame " << i;
    } else {
      EXPECT_EQ(r.person_removed, 0) << "frame " << i;
      EXPECT_EQ(r.wall_removed, 0) << "frame " << i;
    }
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
  const cv::Mat people_depth = personDepth(0.0, 0.0);
  const RemovalBackfill::Points all = personFound(backfill, 0.0, 0.0);
  // The floor at y = 0.3 (image y points down): up = -y, the floor's height along it -0.3.
  const std::pair<Eigen::Vector3d, double> floor{Eigen::Vector3d(0.0, -1.0, 0.0), -0.3};
  const RemovalBackfill::Points above = backfill.personPoints(people_depth, smallCamera(), cameraAt(0.0), floor);
  ASSERT_FALSE(all.empty());
  int expected = 0;
  const double clearance = backfill.options().floor_clearance;
  for (const Eigen::Vector3f& p : all) expected += (0.3 - p.y() >= clearance) ? 1 : 0;
  EXPECT_EQ(static_cast<int>(above.size()), expected);
  EXPECT_LT(above.size(), all.size());
  for (const Eigen::Vector3f& p : above) EXPECT_GE(0.3 - p.y(), clearance - 1e-5);
}

TEST_F(Backfill, APersonsOutlineIsNotCarried) {
  RemovalBackfill backfill;
  cv::Mat person;
  personDepth(0.0, 0.0, &person);
  const RemovalBackfill::Points points = personFound(backfill, 0.0, 0.0);
  const cv::Mat inside = insideOutline(person);
  int expected = 0;
  for (int v = 0; v < inside.rows; v += RemovalBackfill::kStride) {
    for (int u = 0; u < inside.cols; u += RemovalBackfill::kStride) expected += inside.at<uint8_t>(v, u) ? 1 : 0;
  }
  ASSERT_GT(expected, 100);
  EXPECT_EQ(static_cast<int>(points.size()), expected);
  const CameraIntrinsics k = smallCamera();
  for (const Eigen::Vector3f& p : points) {  // camera at the world's origin
    const int u = static_cast<int>(std::lround(k.fx * p.x() / p.z() + k.cx));
    const int v = static_cast<int>(std::lround(k.fy * p.y() / p.z() + k.cy));
    EXPECT_TRUE(inside.at<uint8_t>(v, u)) << u << " " << v;
  }
}

TEST_F(Backfill, TheWallRemovedBesideAPersonWhoLeftIsGivenBack) {
  RemovalBackfill backfill;  // waits 30 frames; 3 of every sixth frame around must see it kept
  // The person walks right 0.1 m a frame, removed with 10 px (15 cm on the wall) around them.
  for (int i = 0; i < 40; ++i) backfill.push(filtered(i, 0.0, -1.0 + 0.1 * i, 10), {});
  ASSERT_EQ(released.size(), 10u);  // frames 0-9, each with 30 later frames
  for (const Released& r : released) {
    ASSERT_GT(r.person_pixels, 2000);
    // Where the person stood, the later frames see the wall 1 m farther: never given back.
    EXPECT_EQ(r.person_removed, r.person_pixels) << "frame " << r.index;
    // The wall around them was seen again, kept, by the later frames: all of it given back.
    EXPECT_EQ(r.wall_removed, 0) << "frame " << r.index;
  }
}

TEST_F(Backfill, APersonWhoStaysAndTheWallNearTheFloorAreNotGivenBack) {
  RemovalBackfill backfill;
  // The person stands still, removed with 10 px around them in every frame; the floor at y = 0.3
  // (image y down: up = -y, the floor's height along it -0.3).
  for (int i = 0; i < 40; ++i) {
    RemovalBackfill::Frame f = filtered(i, 0.0, 0.0, 10);
    f.floor = std::make_pair(Eigen::Vector3d(0.0, -1.0, 0.0), -0.3);
    backfill.push(std::move(f), {});
  }
  ASSERT_EQ(released.size(), 10u);
  const int spill = cv::countNonZero(filtered(0, 0.0, 0.0, 10).removed) - released[0].person_pixels;
  ASSERT_GT(spill, 1000);
  for (const Released& r : released) {
    // The later frames removed the person and the wall around them too: nothing seen kept.
    EXPECT_EQ(r.person_removed, r.person_pixels) << "frame " << r.index;
    EXPECT_EQ(r.wall_removed, spill) << "frame " << r.index;
  }

  // The same while the later frames keep everything: only the wall within 0.1 m of the floor
  // (y > 0.2 on the wall 3 m away: image rows below 120 + 200 * 0.2 / 3) stays removed.
  RemovalBackfill kept;
  released.clear();
  for (int i = 0; i < 40; ++i) {
    RemovalBackfill::Frame f = filtered(i, 0.0, -1.0 + 0.1 * i, i == 0 ? 10 : 0);
    f.floor = std::make_pair(Eigen::Vector3d(0.0, -1.0, 0.0), -0.3);
    kept.push(std::move(f), {});
  }
  ASSERT_FALSE(released.empty());
  const Released& first = released[0];
  const cv::Mat wall_removed = first.removed & ~first.person;
  const int low_row = 120 + 200 * 2 / 30 + 1;
  EXPECT_EQ(cv::countNonZero(wall_removed.rowRange(0, low_row - 1)), 0);
  EXPECT_GT(cv::countNonZero(wall_removed.rowRange(low_row, wall_removed.rows)), 200);
}

TEST_F(Backfill, TheFramesBeforeGiveBackToo) {
  RemovalBackfill backfill;
  // The person walks right 0.1 m a frame; only frame 30 removed them (with 10 px around them), and
  // the frames after it have no pose (tracking lost): only the thirty before it can tell.
  for (int i = 0; i < 61; ++i) {
    RemovalBackfill::Frame f = filtered(i, 0.0, -3.0 + 0.1 * i, i == 30 ? 10 : 0);
    if (i > 30) f.T_w_c.reset();
    backfill.push(std::move(f), {});
  }
  backfill.flush();
  ASSERT_EQ(released.size(), 61u);
  const Released& r = released[30];
  ASSERT_GT(r.person_pixels, 2000);
  EXPECT_EQ(r.person_removed, r.person_pixels);  // the frames before saw the wall behind them
  EXPECT_EQ(r.wall_removed, 0);                   // and the wall beside them, kept

  // Without the frames before (give_back_views = 0: none kept, nothing given back).
  RemovalBackfill::Options options;
  options.give_back_views = 0;
  RemovalBackfill off(options);
  released.clear();
  for (int i = 0; i < 61; ++i) off.push(filtered(i, 0.0, -3.0 + 0.1 * i, i == 30 ? 10 : 0), {});
  off.flush();
  EXPECT_GT(released[30].wall_removed, 1000);
}

TEST_F(Backfill, APersonTheLaterFramesMissNowAndThenIsNotGivenBack) {
  RemovalBackfill backfill;
  // A person standing still, removed (with 10 px around them) in every frame but 6, 12 and 18: of
  // the five later frames frame 0 is looked for in (6, 12, ..., 30) three kept them, two removed
  // them; three are enough, but not twice as many as removed them.
  const auto missedIn = [](int i) { return i == 6 || i == 12 || i == 18; };
  for (int i = 0; i < 31; ++i) backfill.push(filtered(i, 0.0, 0.0, missedIn(i) ? 0 : 10), {});
  ASSERT_EQ(released.size(), 1u);
  EXPECT_EQ(released[0].person_removed, released[0].person_pixels);

  // Removed in frames 0 and 24 only (one of the five removed them, four kept them): taken for a
  // mistake, given back.
  RemovalBackfill missed;
  released.clear();
  for (int i = 0; i < 31; ++i) missed.push(filtered(i, 0.0, 0.0, i == 0 || i == 24 ? 10 : 0), {});
  ASSERT_EQ(released.size(), 1u);
  EXPECT_EQ(released[0].person_removed, 0);
  EXPECT_EQ(released[0].wall_removed, 0);
}

TEST_F(Backfill, APersonNobodyFoundWhoWalkedOnIsRemovedWhereTheFramesAroundSawThroughThem) {
  RemovalBackfill backfill;  // one of every sixth frame around must have seen through
  // The person walks right 0.1 m a frame and the filter removed nothing of them: frames 6, 12, ...
  // later the wall 1 m behind them is where they stood.
  for (int i = 0; i < 40; ++i) backfill.push(filtered(i, 0.0, -1.0 + 0.1 * i, 0), {});
  ASSERT_EQ(released.size(), 10u);
  for (const Released& r : released) {
    ASSERT_GT(r.person_pixels, 2000);
    // One probe per 8 x 8 block found among every second pixel: a column at the person's outline
    // may be missed.
    EXPECT_GE(r.person_removed, 0.97 * r.person_pixels) << "frame " << r.index;
    EXPECT_EQ(r.wall_removed, 0) << "frame " << r.index;  // never seen through
  }

  // Off: nothing removed.
  RemovalBackfill::Options options;
  options.seen_through_views = 0;
  RemovalBackfill off(options);
  released.clear();
  for (int i = 0; i < 40; ++i) off.push(filtered(i, 0.0, -1.0 + 0.1 * i, 0), {});
  ASSERT_EQ(released.size(), 10u);
  for (const Released& r : released) EXPECT_EQ(r.person_removed, 0) << "frame " << r.index;
}

TEST_F(Backfill, AStillSceneIsNotRemovedWhereAPoseOneCentimetreOffLooksPastAnEdge) {
  RemovalBackfill backfill;
  // The patch stands still (a box, say) and nothing is removed; frame 0's pose is 1 cm off to the
  // right, so the column of the box at its edge moves past it in every other frame, onto the wall
  // 1 m behind: only the depth around the pixel there (the box, 1 px away) tells it from free space.
  for (int i = 0; i < 31; ++i) {
    RemovalBackfill::Frame f = filtered(i, 0.0, 0.0, 0);
    if (i == 0) f.T_w_c = cameraAt(0.01);
    backfill.push(std::move(f), {});
  }
  ASSERT_EQ(released.size(), 1u);
  EXPECT_EQ(released[0].person_removed, 0);
  EXPECT_EQ(released[0].wall_removed, 0);
}

TEST_F(Backfill, WhatTwoFramesAroundKeptIsNotRemovedThoughOthersSawThroughIt) {
  RemovalBackfill backfill;
  // The person stands at x = 0 in frames 0-5 and 24-30 and elsewhere in frames 6-23: of the
  // frames frame 0 looks in (6, 12, ..., 30), 24 and 30 kept them there, 6, 12 and 18 saw the wall.
  const auto personAt = [](int i) { return i >= 6 && i < 24 ? 1.0 : 0.0; };
  for (int i = 0; i < 31; ++i) backfill.push(filtered(i, 0.0, personAt(i), 0), {});
  ASSERT_EQ(released.size(), 1u);
  EXPECT_EQ(released[0].person_removed, 0);
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
  bad = RemovalBackfill::Options();
  bad.give_back_floor_clearance = 1.5;
  EXPECT_THROW(RemovalBackfill{bad}, Error);
  bad = RemovalBackfill::Options();
  bad.give_back_views = 11;
  EXPECT_THROW(RemovalBackfill{bad}, Error);
  bad = RemovalBackfill::Options();
  bad.give_back_tolerance = 0.001;
  EXPECT_THROW(RemovalBackfill{bad}, Error);
  bad = RemovalBackfill::Options();
  bad.seen_through_views = 11;
  EXPECT_THROW(RemovalBackfill{bad}, Error);
  bad = RemovalBackfill::Options();
  bad.seen_through_margin = 0.01;
  EXPECT_THROW(RemovalBackfill{bad}, Error);

  RemovalBackfill backfill;
  RemovalBackfill::Frame frame;
  frame.depth = cv::Mat::zeros(4, 4, CV_16U);
  frame.removed = cv::Mat::zeros(4, 4, CV_8U);
  EXPECT_THROW(backfill.push(frame, {}), Error);
  frame.depth = cv::Mat::zeros(4, 4, CV_32F);
  frame.removed = cv::Mat::zeros(4, 5, CV_8U);
  EXPECT_THROW(backfill.push(frame, {}), Error);
  frame.removed = cv::Mat::zeros(4, 4, CV_8U);
  frame.measured = cv::Mat::zeros(4, 4, CV_16U);
  EXPECT_THROW(backfill.push(frame, {}), Error);
}

}  // namespace
}  // namespace pf2
