#include "pf2/io/tum_sequence.h"

#include <sys/stat.h>

#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "pf2/core/error.h"
#include "pf2/io/trajectory_io.h"

namespace pf2 {
namespace {

// Writes a three-frame TUM folder: depth of frame i is (1 + i) metres everywhere.
std::string makeSequence(const std::string& name) {
  const std::string dir = testing::TempDir() + name;
  ::mkdir(dir.c_str(), 0755);
  ::mkdir((dir + "/rgb").c_str(), 0755);
  ::mkdir((dir + "/depth").c_str(), 0755);
  std::ofstream rgb(dir + "/rgb.txt"), depth(dir + "/depth.txt");
  rgb << "# color images\n# timestamp filename\n";
  depth << "# depth maps\r\n";
  for (int i = 0; i < 3; ++i) {
    const double t = 10.0 + i / 30.0;
    const std::string stamp = std::to_string(t);
    cv::imwrite(dir + "/rgb/" + stamp + ".png", cv::Mat(480, 640, CV_8UC3, cv::Scalar(i, 2 * i, 3 * i)));
    cv::imwrite(dir + "/depth/" + stamp + ".png",
                cv::Mat(480, 640, CV_16UC1, cv::Scalar(5000 * (1 + i))));
    rgb << stamp << " rgb/" << stamp << ".png\n";
    depth << std::to_string(t + 0.004) << " depth/" << stamp << ".png\r\n";
  }
  return dir;
}

TEST(TumSequence, ReadsAssociatedFramesLazily) {
  const std::string dir = makeSequence("pf2_seq_ok");
  TumSequence sequence(dir);
  ASSERT_EQ(sequence.size(), 3u);
  EXPECT_DOUBLE_EQ(sequence.intrinsics().fx, 535.4);  // freiburg3 default
  const Frame frame = sequence.frame(2);
  EXPECT_EQ(frame.index, 2);
  EXPECT_NEAR(frame.timestamp, 10.0 + 2 / 30.0, 1e-6);
  ASSERT_EQ(frame.depth.type(), CV_32F);
  EXPECT_FLOAT_EQ(frame.depth.at<float>(100, 100), 3.0f);
  EXPECT_EQ(frame.rgb.at<cv::Vec3b>(0, 0), cv::Vec3b(2, 4, 6));
  EXPECT_FALSE(sequence.hasGroundTruth());
}

TEST(TumSequence, DepthScaleAndCalibrationFile) {
  const std::string dir = makeSequence("pf2_seq_scale");
  std::ofstream(dir + "/camera.txt") << "fx 500\nfy 501\ncx 319.5\ncy 239.5\nwidth 640\nheight 480\n";
  TumSequence::Options options;
  options.depth_scale = 1000.0;
  TumSequence sequence(dir, options);
  EXPECT_DOUBLE_EQ(sequence.intrinsics().fy, 501.0);
  EXPECT_FLOAT_EQ(sequence.frame(0).depth.at<float>(0, 0), 5.0f);
}

TEST(TumSequence, FolderNameSelectsPreset) {
  const std::string dir = makeSequence("rgbd_dataset_freiburg1_xyz");
  EXPECT_DOUBLE_EQ(TumSequence(dir).intrinsics().fx, 517.3);
}

TEST(TumSequence, BonnFolderWithoutCalibrationUsesBonnPreset) {
  // As published: no camera.txt (removed in case an earlier run of this test left one).
  const std::string dir = makeSequence("rgbd_bonn_xxx");
  std::remove((dir + "/camera.txt").c_str());
  const CameraIntrinsics k = TumSequence(dir + "/").intrinsics();
  EXPECT_DOUBLE_EQ(k.fx, 542.822841);
  EXPECT_DOUBLE_EQ(k.fy, 542.576870);
  EXPECT_DOUBLE_EQ(k.cx, 315.593520);
  EXPECT_DOUBLE_EQ(k.cy, 237.756098);
  EXPECT_TRUE(isBonnDynamicFolder(dir));
  EXPECT_FALSE(isBonnDynamicFolder(testing::TempDir() + "my_rgbd_bonn_copy"));
  // Its groundtruth.txt holds marker poses: groundTruth() hands out camera poses.
  std::ofstream(dir + "/groundtruth.txt") << "# Bonn marker poses\n"
                                          << "10.0 -0.451159 -1.61241 1.52569 0.16492 0.0766074 -0.0125995 -0.983247\n";
  const Trajectory cameras = TumSequence(dir).groundTruth();
  const Trajectory converted = readTrajectory(dir + "/groundtruth.txt", TrajectoryFormat::kBonn);
  const Trajectory as_written = readTrajectory(dir + "/groundtruth.txt", TrajectoryFormat::kTum);
  ASSERT_EQ(cameras.size(), 1u);
  EXPECT_LT((cameras[0].T_w_c.matrix() - converted[0].T_w_c.matrix()).norm(), 1e-12);
  EXPECT_GT((cameras[0].T_w_c.matrix() - as_written[0].T_w_c.matrix()).norm(), 0.1);
  std::remove((dir + "/groundtruth.txt").c_str());
  // A camera.txt in the folder still wins over the preset.
  std::ofstream(dir + "/camera.txt") << "fx 500\nfy 501\ncx 319.5\ncy 239.5\nwidth 640\nheight 480\n";
  EXPECT_DOUBLE_EQ(TumSequence(dir).intrinsics().fx, 500.0);
  std::remove((dir + "/camera.txt").c_str());
}

TEST(TumSequence, MissingPiecesAreNamed) {
  const std::string dir = makeSequence("pf2_seq_broken");
  // Missing image: the error names it.
  const std::string stamp = std::to_string(10.0 + 1 / 30.0);
  std::remove((dir + "/depth/" + stamp + ".png").c_str());
  TumSequence sequence(dir);
  try {
    sequence.frame(1);
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("depth/" + stamp + ".png"), std::string::npos) << e.what();
  }
  // A depth image of the wrong type.
  cv::imwrite(dir + "/depth/" + stamp + ".png", cv::Mat(480, 640, CV_8UC1, cv::Scalar(1)));
  EXPECT_THROW(sequence.frame(1), Error);
  // Missing list, missing folder, nothing to associate.
  std::remove((dir + "/depth.txt").c_str());
  EXPECT_THROW(TumSequence{dir}, Error);
  EXPECT_THROW(TumSequence{dir + "/nope"}, Error);
  std::ofstream(dir + "/depth.txt") << "99.0 depth/x.png\n";
  EXPECT_THROW(TumSequence{dir}, Error);
}

TEST(TumSequence, RealTumFramesWhenPresent) {
  const std::string dir = std::string(PF2_SHARED_DATA) + "/tum_fr1_desk_9";
  struct stat info;
  if (::stat(dir.c_str(), &info) != 0) GTEST_SKIP() << "no real data at " << dir;
  TumSequence sequence(dir);
  EXPECT_EQ(sequence.size(), 9u);
  EXPECT_DOUBLE_EQ(sequence.intrinsics().fx, 517.3);  // "fr1" in the folder name
  EXPECT_TRUE(sequence.hasGroundTruth());
  EXPECT_GT(sequence.groundTruth().size(), 9u);
  const Frame frame = sequence.frame(0);
  EXPECT_EQ(frame.depth.cols, 640);
  double valid = cv::countNonZero(frame.depth > 0) / double(frame.depth.total());
  EXPECT_GT(valid, 0.5);  // a real Kinect frame is mostly measured
  double lo, hi;
  cv::minMaxLoc(frame.depth, &lo, &hi);
  EXPECT_GT(hi, 0.5);
  EXPECT_LT(hi, 10.0);
}

}  // namespace
}  // namespace pf2
