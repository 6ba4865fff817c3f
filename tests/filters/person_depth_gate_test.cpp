#include "pf2/filters/person_depth_gate.h"

#include <gtest/gtest.h>

namespace pf2 {
namespace {

// An 80x60 scene: a wall at 3 m and a person (cols 30..39, rows 10..49) whose core leans back,
// 1.5 m at the top (rows 10..29) and 2.5 m at the bottom (rows 30..49).
struct GateScene {
  cv::Mat depth = cv::Mat(60, 80, CV_32F, cv::Scalar(3.0f));
  cv::Mat core = cv::Mat::zeros(60, 80, CV_8U);
  GateScene() {
    depth(cv::Rect(30, 10, 10, 20)).setTo(1.5f);
    depth(cv::Rect(30, 30, 10, 20)).setTo(2.5f);
    core(cv::Rect(30, 10, 10, 40)).setTo(255);
  }
};

PersonDepthGate gate(int radius, double margin) { return PersonDepthGate(PersonDepthGate::Options{radius, margin}); }

TEST(PersonDepthGate, MarksDepthApartFromThePersonsDepthAroundIt) {
  GateScene s;
  s.depth.at<float>(12, 25) = 2.0f;  // 0.5 m behind the shoulder beside it: apart
  s.depth.at<float>(14, 26) = 1.7f;  // 0.2 m behind it, within the margin: not apart
  s.depth.at<float>(14, 27) = 1.1f;  // 0.4 m in front of it: apart
  s.depth.at<float>(16, 25) = 0.f;   // no measurement: never
  const cv::Mat apart = gate(10, 0.3).outsidePeople(s.depth, s.core);
  ASSERT_EQ(apart.size(), s.depth.size());
  EXPECT_EQ(apart.at<uint8_t>(12, 25), 255);
  EXPECT_EQ(apart.at<uint8_t>(14, 26), 0);
  EXPECT_EQ(apart.at<uint8_t>(14, 27), 255);
  EXPECT_EQ(apart.at<uint8_t>(16, 25), 0);
  EXPECT_EQ(apart.at<uint8_t>(20, 35), 0) << "the person's own depth";
  EXPECT_EQ(apart.at<uint8_t>(20, 45), 255) << "the wall 1.5 m behind the shoulder";
  // 13 px from the person: more than the radius (10 px, 11 at half resolution) away.
  EXPECT_EQ(apart.at<uint8_t>(20, 17), 0);
}

// The window's own depths decide: the same 2.2 m is apart from the person's top (1.5 m) and not
// from their bottom (2.5 m), which lies more than the radius away from the top's side.
TEST(PersonDepthGate, IsLocal) {
  GateScene s;
  s.depth.at<float>(12, 26) = 2.2f;
  s.depth.at<float>(47, 26) = 2.2f;
  const cv::Mat apart = gate(10, 0.3).outsidePeople(s.depth, s.core);
  EXPECT_EQ(apart.at<uint8_t>(12, 26), 255);
  EXPECT_EQ(apart.at<uint8_t>(47, 26), 0);
  // Both within the window of rows 25..34, which holds 1.5 and 2.5 m: 2.2 m lies between them.
  s.depth.at<float>(30, 26) = 2.2f;
  EXPECT_EQ(gate(10, 0.3).outsidePeople(s.depth, s.core).at<uint8_t>(30, 26), 0);
}

TEST(PersonDepthGate, OffWithoutRadiusOrCore) {
  GateScene s;
  EXPECT_TRUE(gate(0, 0.3).outsidePeople(s.depth, s.core).empty());
  EXPECT_TRUE(gate(10, 0.3).outsidePeople(s.depth, cv::Mat::zeros(60, 80, CV_8U)).empty());
  // A core without measured depth has no depth to compare with: nothing is apart.
  s.depth(cv::Rect(30, 10, 10, 40)).setTo(0.f);
  const cv::Mat apart = gate(10, 0.3).outsidePeople(s.depth, s.core);
  EXPECT_EQ(cv::countNonZero(apart), 0);
}

}  // namespace
}  // namespace pf2
