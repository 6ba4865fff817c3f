#include "pf2/filters/mask_metrics.h"

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

TEST(MaskMetrics, CountsRecallPrecisionRetention) {
  cv::Mat input(10, 10, CV_32F, cv::Scalar(2.f));
  input.at<float>(0, 0) = 0.f;  // no depth: not counted anywhere
  cv::Mat gt = cv::Mat::zeros(10, 10, CV_16U);
  gt(cv::Rect(0, 0, 4, 5)).setTo(3);  // 20 person pixels, 19 with depth
  cv::Mat output = input.clone();
  output(cv::Rect(0, 0, 4, 4)).setTo(0.f);  // 15 of them removed, 4 kept
  output(cv::Rect(8, 8, 2, 2)).setTo(0.f);  // 4 static pixels removed
  const MaskCounts c = countMaskAgreement(input, output, gt);
  EXPECT_EQ(c.person, 19);
  EXPECT_EQ(c.person_removed, 15);
  EXPECT_EQ(c.static_total, 80);
  EXPECT_EQ(c.static_kept, 76);
  EXPECT_DOUBLE_EQ(c.recall(), 15.0 / 19.0);
  EXPECT_DOUBLE_EQ(c.precision(), 76.0 / 80.0);
  EXPECT_DOUBLE_EQ(c.retention(), 76.0 / 80.0);
  MaskCounts total = c;
  total += c;
  EXPECT_EQ(total.frames, 2);
  EXPECT_DOUBLE_EQ(total.recall(), 15.0 / 19.0);
  EXPECT_THROW(countMaskAgreement(input, output, cv::Mat::zeros(5, 5, CV_8U)), Error);
}

}  // namespace
}  // namespace pf2
