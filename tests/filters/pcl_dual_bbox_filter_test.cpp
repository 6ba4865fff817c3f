#include "pf2/filters/pcl_dual_bbox_filter.h"

#include <cmath>

#include <gtest/gtest.h>
#include <pcl/point_types.h>

namespace pf2 {
namespace {

TEST(PclDualBBoxFilter, SameResultAsTheImagePath) {
  cv::Mat depth(30, 40, CV_32F, cv::Scalar(3.02f));
  depth(cv::Rect(15, 10, 10, 15)).setTo(1.52f);
  depth.at<float>(12, 13) = 1.6f;
  depth.at<float>(27, 20) = 2.5f;
  depth.at<float>(5, 5) = 0.f;
  Detections detections;
  detections.people.resize(1);
  detections.people[0].box = PersonBox{14, 9, 26, 26};
  detections.people[0].score = 0.9f;
  const CameraIntrinsics K{30, 30, 20, 15, 40, 30};

  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>(40, 30);
  for (int v = 0; v < 30; ++v) {
    for (int u = 0; u < 40; ++u) {
      const float z = depth.at<float>(v, u);
      const Eigen::Vector3d p = K.backProject(u, v, z);
      cloud->at(u, v) = z > 0 ? pcl::PointXYZ(p.x(), p.y(), p.z()) : pcl::PointXYZ(NAN, NAN, NAN);
    }
  }
  DualBBoxFilter::Options options;
  options.human_histogram = HistogramOptions{0.05, 10.0, 0.4, 0.25, 0.6};
  DualBBoxFilter image_filter(options);
  const auto expected = image_filter.filter(depth, detections);

  PclDualBBoxFilter<pcl::PointXYZ> filter(options);
  filter.setInputCloud(cloud);
  filter.setDetections(detections);
  pcl::PointCloud<pcl::PointXYZ> organized;
  filter.filter(organized);
  ASSERT_EQ(organized.width, 40u);
  ASSERT_EQ(organized.height, 30u);
  int kept = 0;
  for (int v = 0; v < 30; ++v) {
    for (int u = 0; u < 40; ++u) {
      const bool point_kept = std::isfinite(organized.at(u, v).z);
      EXPECT_EQ(point_kept, expected.static_depth.at<float>(v, u) > 0) << u << "," << v;
      kept += point_kept;
    }
  }
  EXPECT_EQ(kept, cv::countNonZero(expected.static_depth));
  EXPECT_EQ(kept, 40 * 30 - 1 - 150 - 2);

  filter.setKeepOrganized(false);
  pcl::PointCloud<pcl::PointXYZ> dense;
  filter.filter(dense);
  EXPECT_EQ(static_cast<int>(dense.size()), kept);

  // The paper's setters reach the core: lambda = 1 keeps the ring pixels.
  filter.setBoxScale(1.0);
  filter.filter(dense);
  EXPECT_EQ(static_cast<int>(dense.size()), kept + 2);
}

TEST(PclDualBBoxFilter, RejectsUnorganizedClouds) {
  auto cloud = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  cloud->push_back(pcl::PointXYZ(0, 0, 1));
  PclDualBBoxFilter<pcl::PointXYZ> filter;
  filter.setInputCloud(cloud);
  pcl::PointCloud<pcl::PointXYZ> out;
  EXPECT_THROW(filter.filter(out), Error);
}

}  // namespace
}  // namespace pf2
