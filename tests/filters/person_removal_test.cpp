#include "pf2/filters/person_removal.h"

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

// Reports one person, box (14, 9)-(26, 26), on every frame.
class OnePersonDetector : public HumanDetector {
 public:
  std::string name() const override { return "one-person"; }
  Detections detect(const Frame& frame) override {
    Detections d;
    d.timestamp = frame.timestamp;
    PersonDetection p;
    p.box = PersonBox{14, 9, 26, 26};
    p.score = 0.9f;
    d.people.push_back(p);
    return d;
  }
};

// A 40x30 frame: wall at 3 m, the person (cols 15..24, rows 10..24) at 1.5 m.
Frame sceneFrame() {
  Frame frame;
  frame.timestamp = 1.0;
  frame.intrinsics = CameraIntrinsics{30, 30, 20, 15, 40, 30};
  frame.depth = cv::Mat(30, 40, CV_32F, cv::Scalar(3.0f));
  frame.depth(cv::Rect(15, 10, 10, 15)).setTo(1.5f);
  frame.rgb = cv::Mat(30, 40, CV_8UC3, cv::Scalar::all(128));
  return frame;
}

TEST(PersonRemoval, DetectsFiltersAndTimesBothStages) {
  PersonRemoval removal(PersonRemoval::Options(), std::make_unique<OnePersonDetector>());
  EXPECT_EQ(removal.detector().name(), "one-person");
  const Frame frame = sceneFrame();
  StageStats stats;
  const Detections detections = removal.detect(frame, &stats);
  ASSERT_EQ(detections.people.size(), 1u);
  const DualBBoxFilter::Result r =
      removal.filter(frame, detections, Eigen::Isometry3d::Identity(), cv::Mat(), &stats);
  EXPECT_EQ(cv::countNonZero(r.static_depth(cv::Rect(15, 10, 10, 15))), 0);  // the person, removed
  EXPECT_EQ(r.static_depth.at<float>(2, 2), 3.0f);                          // the wall, kept
  EXPECT_EQ(stats.summary("detect").count, 1);
  EXPECT_EQ(stats.summary("filter").count, 1);
}

TEST(PersonRemoval, DegradesDetectionsAndUsesThePrediction) {
  PersonRemoval::Options options;
  options.degradation.drop_probability = 1.0;  // the person is always missed
  options.filter.geometric = true;
  PersonRemoval removal(options, std::make_unique<OnePersonDetector>());
  const Frame frame = sceneFrame();
  StageStats stats;
  const Detections none = removal.detect(frame, &stats);
  EXPECT_TRUE(none.people.empty());
  // Without a detection only the prediction finds the person: depth 1.5 m in front of a 3 m wall.
  const cv::Mat wall(30, 40, CV_32F, cv::Scalar(3.0f));
  EXPECT_EQ(cv::countNonZero(removal.filter(frame, none, Eigen::Isometry3d::Identity(), cv::Mat(), &stats).removed), 0);
  const DualBBoxFilter::Result r = removal.filter(frame, none, Eigen::Isometry3d::Identity(), wall, &stats);
  EXPECT_EQ(cv::countNonZero(r.removed), 150);
  EXPECT_THROW(PersonRemoval(options, nullptr), Error);
}

}  // namespace
}  // namespace pf2
