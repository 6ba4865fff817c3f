#include "pf2/synth/depth_sensor_model.h"

#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

// A fronto-parallel wall at depth z filling the image.
cv::Mat wall(const CameraIntrinsics& K, float z) { return cv::Mat(K.height, K.width, CV_32F, cv::Scalar(z)); }

TEST(DepthSensorModel, NoiseGrowsWithDepthAsNguyenEtAl) {
  const CameraIntrinsics K = CameraIntrinsics::tumFreiburg3();
  const DepthSensorModel sensor;
  double previous = 0.0;
  for (const float z : {0.8f, 1.5f, 2.5f, 3.5f}) {
    const cv::Mat noisy = sensor.apply(wall(K, z), K, 42);
    double sum = 0.0, sum2 = 0.0;
    int n = 0;
    for (int v = 0; v < noisy.rows; ++v) {
      for (int u = 0; u < noisy.cols; ++u) {
        const float d = noisy.at<float>(v, u);
        if (d == 0.0f) continue;
        sum += d - z;
        sum2 += (d - z) * (d - z);
        ++n;
      }
    }
    ASSERT_GT(n, noisy.total() * 0.95) << "a plain wall has no holes";
    const double mean = sum / n, std_dev = std::sqrt(sum2 / n - mean * mean);
    // Gaussian axial noise plus disparity quantisation (step^2 / 12 in variance).
    const double step = z * z * sensor.options().disparity_step / (K.fx * sensor.options().baseline);
    const double expected = std::sqrt(std::pow(sensor.sigma(z), 2) + step * step / 12.0);
    EXPECT_NEAR(std_dev, expected, 0.15 * expected) << "z = " << z;
    EXPECT_LT(std::abs(mean), 0.3 * expected) << "z = " << z;
    EXPECT_GT(std_dev, previous * 1.3);
    previous = std_dev;
  }
  EXPECT_NEAR(sensor.sigma(0.4), 0.0012, 1e-12);
  EXPECT_NEAR(sensor.sigma(3.4), 0.0012 + 0.0019 * 9.0, 1e-12);
}

TEST(DepthSensorModel, NothingOutsideTheRange) {
  const CameraIntrinsics K = CameraIntrinsics::tumFreiburg3().scaled(0.5);
  cv::Mat depth(K.height, K.width, CV_32F);
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) depth.at<float>(v, u) = 0.1f + 6.0f * u / depth.cols;
  }
  for (const bool noise : {true, false}) {
    DepthSensorModel::Options options;
    options.noise = noise;
    const cv::Mat out = DepthSensorModel(options).apply(depth, K, 3);
    int valid = 0;
    for (int v = 0; v < out.rows; ++v) {
      for (int u = 0; u < out.cols; ++u) {
        const float d = out.at<float>(v, u);
        if (d == 0.0f) continue;
        ++valid;
        ASSERT_GE(d, 0.4f);
        ASSERT_LE(d, 4.5f);
      }
    }
    EXPECT_GT(valid, out.total() / 2);
  }
}

TEST(DepthSensorModel, ForegroundEdgesCastProjectorShadowsToTheLeft) {
  const CameraIntrinsics K = CameraIntrinsics::tumFreiburg3();
  cv::Mat depth = wall(K, 3.0f);
  depth(cv::Rect(300, 100, 100, 200)).setTo(1.0f);  // a box 1 m away in front of a 3 m wall
  const DepthSensorModel sensor;
  const cv::Mat out = sensor.apply(depth, K, 5);
  // Shadow width in pixels: fx b (1/z_near - 1/z_far).
  const double width = K.fx * sensor.options().baseline * (1.0 / 1.0 - 1.0 / 3.0);
  const int row = 200;
  int shadow = 0;
  for (int u = 299; u >= 250; --u) shadow += out.at<float>(row, u) == 0.0f;
  EXPECT_NEAR(shadow, width, 3.0);
  int right_holes = 0;  // the right side of the box stays lit (mixed-pixel holes only)
  for (int u = 402; u < 450; ++u) right_holes += out.at<float>(row, u) == 0.0f;
  EXPECT_LE(right_holes, 1);
}

TEST(DepthSensorModel, MisalignmentShiftsByTheAskedPixels) {
  const CameraIntrinsics K = CameraIntrinsics::tumFreiburg3().scaled(0.5);
  cv::Mat depth(K.height, K.width, CV_32F);
  for (int v = 0; v < depth.rows; ++v) {
    for (int u = 0; u < depth.cols; ++u) depth.at<float>(v, u) = 1.0f + 0.01f * ((u * 7 + v * 3) % 50);
  }
  DepthSensorModel::Options options;
  options.noise = false;
  const cv::Mat aligned = DepthSensorModel(options).apply(depth, K, 1);
  for (const int shift : {3, -2}) {
    options.misalign_px = shift;
    const cv::Mat shifted = DepthSensorModel(options).apply(depth, K, 1);
    for (int v = 0; v < depth.rows; ++v) {
      for (int u = std::max(0, -shift); u < std::min(depth.cols, depth.cols - shift); ++u) {
        ASSERT_EQ(shifted.at<float>(v, u + shift), aligned.at<float>(v, u)) << shift;
      }
    }
  }
}

TEST(DepthSensorModel, SameSeedSameNoise) {
  const CameraIntrinsics K = CameraIntrinsics::tumFreiburg3().scaled(0.25);
  const DepthSensorModel sensor;
  const cv::Mat a = sensor.apply(wall(K, 2.0f), K, 11), b = sensor.apply(wall(K, 2.0f), K, 11);
  const cv::Mat c = sensor.apply(wall(K, 2.0f), K, 12);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0);
  EXPECT_GT(cv::norm(a, c, cv::NORM_INF), 0.0);
}

TEST(DepthSensorModel, RejectsAnEmptyRange) {
  DepthSensorModel::Options options;
  options.max_depth = 0.3;
  EXPECT_THROW(DepthSensorModel{options}, Error);
}

}  // namespace
}  // namespace pf2
