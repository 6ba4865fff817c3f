// The filter's internal image helpers (filters/src/image_ops.h).
#include "image_ops.h"

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace pf2 {
namespace {

// Sparse random pixels plus a filled blob touching the border, so the disc's rows, its ends and
// the image's edges all matter.
cv::Mat testMask(int rows, int cols, unsigned seed) {
  cv::RNG rng(seed);
  cv::Mat mask(rows, cols, CV_8U);
  rng.fill(mask, cv::RNG::UNIFORM, 0, 100);
  mask = mask > 97;
  cv::ellipse(mask, cv::Point(cols - 5, rows / 2), cv::Size(cols / 4, rows / 5), 30, 0, 360, cv::Scalar(255), -1);
  return mask;
}

TEST(ImageOps, DilatedByDiscEqualsOpenCvsEllipticDilation) {
  for (int radius : {0, 1, 2, 3, 4, 7, 12, 20, 33}) {
    const cv::Mat mask = testMask(97, 131, static_cast<unsigned>(radius + 1));
    cv::Mat expected;
    cv::dilate(mask, expected,
               cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * radius + 1, 2 * radius + 1)),
               cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    const cv::Mat got = dilatedByDisc(mask, radius);
    ASSERT_EQ(got.size(), mask.size());
    EXPECT_EQ(cv::countNonZero(got != expected), 0) << "radius " << radius;
    if (radius > 0) {
      EXPECT_GT(cv::countNonZero(got), cv::countNonZero(mask)) << "radius " << radius;
    }
  }
}

TEST(ImageOps, DilatedOnAreaGrowsTheMasksBoundsAndClipsThem) {
  cv::Mat mask(60, 80, CV_8U, cv::Scalar(0));
  mask(cv::Rect(2, 30, 10, 5)).setTo(255);
  cv::Rect area;
  const cv::Mat grown = dilatedOnArea(mask, 4, &area);
  EXPECT_EQ(area, cv::Rect(0, 26, 16, 13));  // x clipped at the image's left edge
  ASSERT_EQ(grown.size(), area.size());
  EXPECT_EQ(grown.at<uchar>(4, 2), 255);     // the mask's corner (2, 30)
  EXPECT_EQ(grown.at<uchar>(0, 2), 255);     // 4 pixels above it
  EXPECT_EQ(grown.at<uchar>(0, 15), 0);      // beyond the disc diagonally
  EXPECT_TRUE(dilatedOnArea(cv::Mat(10, 10, CV_8U, cv::Scalar(0)), 3, &area).empty());
  EXPECT_TRUE(area.empty());
}

}  // namespace
}  // namespace pf2
