#include "pf2/eval/trajectory_plot.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

AteResult circleAte() {
  Trajectory gt, est;
  for (int i = 0; i < 100; ++i) {
    StampedPose pose;
    pose.timestamp = i;
    pose.T_w_c.translation() = Eigen::Vector3d(std::cos(i * 0.063), 0.0, std::sin(i * 0.063));
    gt.push_back(pose);
    pose.T_w_c.translation() *= 1.0 + 0.05 * std::sin(i * 0.3);
    est.push_back(pose);
  }
  return computeAte(gt, est);
}

TEST(TrajectoryPlot, PngShowsBothTrajectoriesInTheXzPlane) {
  const std::string path = testing::TempDir() + "pf2_plot.png";
  plotTrajectories(circleAte(), path);
  const cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  ASSERT_FALSE(image.empty());
  EXPECT_EQ(image.cols, 800);
  // Black (ground truth) and blue (estimate) strokes are both present in quantity.
  cv::Mat black, blue;
  cv::inRange(image, cv::Scalar(0, 0, 0), cv::Scalar(40, 40, 40), black);
  cv::inRange(image, cv::Scalar(150, 50, 0), cv::Scalar(255, 130, 60), blue);
  EXPECT_GT(cv::countNonZero(black), 2000);
  EXPECT_GT(cv::countNonZero(blue), 1000);
}

TEST(TrajectoryPlot, SvgHasOneErrorSegmentPerPair) {
  const std::string path = testing::TempDir() + "pf2_plot.svg";
  plotTrajectories(circleAte(), path);
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  const std::string svg = text.str();
  size_t lines = 0;
  for (size_t at = svg.find("<line "); at != std::string::npos; at = svg.find("<line ", at + 1)) ++lines;
  EXPECT_EQ(lines, 100u);
  EXPECT_NE(svg.find("plane x-z"), std::string::npos);
}

TEST(TrajectoryPlot, UnknownExtensionIsAnError) {
  EXPECT_THROW(plotTrajectories(circleAte(), testing::TempDir() + "pf2_plot.jpg2"), Error);
}

}  // namespace
}  // namespace pf2
