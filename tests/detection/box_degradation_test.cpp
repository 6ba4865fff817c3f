#include "pf2/detection/box_degradation.h"

#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace pf2 {
namespace {

Detections frame(double t, int people) {
  Detections d;
  d.timestamp = t;
  for (int i = 0; i < people; ++i) {
    PersonDetection p;
    p.box = PersonBox{100.f + 150 * i, 100, 200.f + 150 * i, 400};
    p.score = 1;
    d.people.push_back(p);
  }
  return d;
}

bool sameBoxes(const Detections& a, const Detections& b) {
  if (a.people.size() != b.people.size()) return false;
  for (size_t i = 0; i < a.people.size(); ++i) {
    const PersonBox &x = a.people[i].box, &y = b.people[i].box;
    if (x.x_ul != y.x_ul || x.y_ul != y.y_ul || x.x_lr != y.x_lr || x.y_lr != y.y_lr) return false;
    if (a.people[i].score != b.people[i].score) return false;
  }
  return true;
}

TEST(BoxDegradation, DeterministicPerFrameWhateverTheOrder) {
  BoxDegradation d;
  d.shift = 5;
  d.drop_probability = 0.3;
  d.false_positive_rate = 1.0;
  d.seed = 7;
  const cv::Size image(640, 480);
  std::vector<Detections> forward, backward(50);
  for (int i = 0; i < 50; ++i) {
    forward.push_back(frame(i / 30.0, 3));
    degradeDetections(d, image, &forward.back());
  }
  for (int i = 49; i >= 0; --i) {
    backward[i] = frame(i / 30.0, 3);
    degradeDetections(d, image, &backward[i]);
  }
  int dropped = 0, added = 0, changed_by_seed = 0;
  for (int i = 0; i < 50; ++i) {
    EXPECT_TRUE(sameBoxes(forward[i], backward[i])) << i;
    int real = 0;
    for (const auto& p : forward[i].people) {
      const bool fake = p.score < 1;
      added += fake;
      if (!fake) {
        ++real;
        // Shifted by 5 px in some direction, size unchanged.
        const double du = p.box.x_ul - std::round((p.box.x_ul - 100) / 150) * 150 - 100;
        const double dv = p.box.y_ul - 100;
        EXPECT_NEAR(std::hypot(du, dv), 5.0, 1e-3);
        EXPECT_FLOAT_EQ(p.box.width(), 100.f);
        EXPECT_GT(p.score, 0.5f);
      }
    }
    dropped += 3 - real;
    Detections other = frame(i / 30.0, 3);
    BoxDegradation d2 = d;
    d2.seed = 8;
    degradeDetections(d2, image, &other);
    changed_by_seed += !sameBoxes(other, forward[i]);
  }
  // 150 people at p = 0.3 and 50 frames at rate 1: well inside 5 sigma of 45 and 50.
  EXPECT_GT(dropped, 20);
  EXPECT_LT(dropped, 75);
  EXPECT_GT(added, 20);
  EXPECT_LT(added, 90);
  EXPECT_GT(changed_by_seed, 40);
}

TEST(BoxDegradation, ShrinkAboutTheCentreAndClip) {
  BoxDegradation d;
  d.shrink = 0.2;
  Detections det = frame(0, 1);
  det.people[0].box = PersonBox{600, 100, 700, 300};  // partly outside a 640 px image
  degradeDetections(d, cv::Size(640, 480), &det);
  ASSERT_EQ(det.people.size(), 1u);
  EXPECT_FLOAT_EQ(det.people[0].box.x_ul, 610.f);
  EXPECT_FLOAT_EQ(det.people[0].box.x_lr, 640.f);  // 690 clipped
  EXPECT_FLOAT_EQ(det.people[0].box.y_ul, 120.f);
  EXPECT_FLOAT_EQ(det.people[0].box.y_lr, 280.f);
  Detections untouched = frame(0, 2);
  degradeDetections(BoxDegradation(), cv::Size(640, 480), &untouched);
  EXPECT_TRUE(sameBoxes(untouched, frame(0, 2)));
}

TEST(BoxDegradation, MaskMovesWithTheBox) {
  BoxDegradation d;
  d.shift = 3;
  Detections det = frame(1.0, 1);
  det.people[0].mask = cv::Mat::zeros(480, 640, CV_8U);
  det.people[0].mask(cv::Rect(100, 100, 100, 300)).setTo(255);
  const cv::Mat before = det.people[0].mask.clone();
  degradeDetections(d, cv::Size(640, 480), &det);
  const cv::Rect moved = cv::boundingRect(det.people[0].mask);
  EXPECT_NEAR(moved.x - 100, std::round(det.people[0].box.x_ul - 100), 1e-6);
  EXPECT_NEAR(moved.y - 100, std::round(det.people[0].box.y_ul - 100), 1e-6);
  EXPECT_EQ(cv::countNonZero(det.people[0].mask), cv::countNonZero(before));
}

}  // namespace
}  // namespace pf2
