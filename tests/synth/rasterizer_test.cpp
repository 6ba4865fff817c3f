#include "pf2/synth/rasterizer.h"

#include <cmath>

#include <gtest/gtest.h>

namespace pf2 {
namespace {

// A square of side `size` centred at `centre` (camera = world frame here), facing the camera (-z).
RenderMesh square(const Eigen::Vector3f& centre, float size, std::uint16_t label, float shade) {
  RenderMesh mesh;
  const float h = size / 2;
  mesh.vertices = {centre + Eigen::Vector3f(-h, -h, 0), centre + Eigen::Vector3f(-h, h, 0),
                   centre + Eigen::Vector3f(h, h, 0), centre + Eigen::Vector3f(h, -h, 0)};
  // Counter-clockwise seen from the camera at the origin (x right, y down).
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.colors.assign(4, Eigen::Vector3f::Constant(shade));
  mesh.label = label;
  mesh.computeVertexNormals();
  return mesh;
}

CameraIntrinsics smallCamera() { return CameraIntrinsics::tumFreiburg3().scaled(0.25); }  // 160x120

TEST(Rasterizer, FrontoParallelSquareHasExactDepthAndLabel) {
  const RenderMesh mesh = square({0, 0, 2}, 1.0f, 7, 0.8f);
  Rasterizer::Options options;
  options.light_position_w = Eigen::Vector3d(0, 0, 0);  // light at the camera: full Lambert
  Rasterizer rasterizer(options);
  RenderedImages out;
  const CameraIntrinsics K = smallCamera();
  rasterizer.render({&mesh}, {}, K, Eigen::Isometry3d::Identity(), &out);
  int covered = 0;
  for (int v = 0; v < K.height; ++v) {
    for (int u = 0; u < K.width; ++u) {
      const Eigen::Vector3d ray = K.backProject(u, v, 2.0);
      const bool inside = std::abs(ray.x()) < 0.5 && std::abs(ray.y()) < 0.5;
      const bool near_edge = std::abs(std::abs(ray.x()) - 0.5) < 0.02 || std::abs(std::abs(ray.y()) - 0.5) < 0.02;
      if (near_edge) continue;
      if (inside) {
        ++covered;
        EXPECT_NEAR(out.depth.at<float>(v, u), 2.0f, 1e-5f);
        EXPECT_EQ(out.labels.at<std::uint16_t>(v, u), 7);
      } else {
        EXPECT_EQ(out.depth.at<float>(v, u), 0.0f);
        EXPECT_EQ(out.labels.at<std::uint16_t>(v, u), 0);
      }
    }
  }
  EXPECT_GT(covered, 1000);
  // Centre pixel: albedo 0.8 x (ambient + diffuse x cos ~ 1).
  const cv::Vec3b centre = out.bgr.at<cv::Vec3b>(static_cast<int>(K.cy), static_cast<int>(K.cx));
  const double expected = 0.8 * (options.ambient + options.diffuse) * 255.0;
  EXPECT_NEAR(centre[0], std::min(255.0, expected), 3.0);
}

TEST(Rasterizer, NearerSurfaceWinsAndBackFacesAreCulled) {
  const RenderMesh far = square({0, 0, 3}, 2.0f, 1, 0.5f);
  const RenderMesh near = square({0.3f, 0, 1.5f}, 0.4f, 2, 0.5f);
  RenderMesh backwards = square({0, 0, 1.0f}, 0.2f, 3, 0.5f);
  for (auto& t : backwards.triangles) std::swap(t[1], t[2]);
  RenderedImages out;
  const CameraIntrinsics K = smallCamera();
  Rasterizer().render({&far, &near, &backwards}, {}, K, Eigen::Isometry3d::Identity(), &out);
  const Eigen::Vector2d on_near = K.project({0.3, 0.0, 1.5});
  const Eigen::Vector2d on_far = K.project({-0.7, 0.0, 3.0});
  const Eigen::Vector2d centre = K.project({0.0, 0.0, 1.0});
  EXPECT_EQ(out.labels.at<std::uint16_t>(std::lround(on_near.y()), std::lround(on_near.x())), 2);
  EXPECT_NEAR(out.depth.at<float>(std::lround(on_near.y()), std::lround(on_near.x())), 1.5f, 1e-5f);
  EXPECT_EQ(out.labels.at<std::uint16_t>(std::lround(on_far.y()), std::lround(on_far.x())), 1);
  // The culled square would cover the image centre; behind it lies the far square.
  EXPECT_EQ(out.labels.at<std::uint16_t>(std::lround(centre.y()), std::lround(centre.x())), 1);
}

TEST(Rasterizer, FloorReachingBehindTheCameraIsClippedNotLost) {
  // A floor 1 m below the camera (y down), from 5 m behind to 5 m ahead.
  RenderMesh floor;
  floor.vertices = {{-5, 1, -5}, {5, 1, -5}, {5, 1, 5}, {-5, 1, 5}};
  floor.triangles = {{0, 1, 2}, {0, 2, 3}};
  floor.colors.assign(4, Eigen::Vector3f::Constant(0.5f));
  floor.cull_back_faces = false;
  RenderedImages out;
  const CameraIntrinsics K = smallCamera();
  Rasterizer().render({&floor}, {}, K, Eigen::Isometry3d::Identity(), &out);
  int checked = 0;
  for (int v = static_cast<int>(K.cy) + 2; v < K.height; ++v) {
    for (int u = 0; u < K.width; ++u) {
      // The ray through (u, v) meets y = 1 at z = fy / (v - cy).
      const double z = K.fy / (v - K.cy);
      if (z > 4.9) continue;
      ASSERT_NEAR(out.depth.at<float>(v, u), z, 1e-4 * z) << u << " " << v;
      ++checked;
    }
  }
  EXPECT_GT(checked, 3000);
}

TEST(Rasterizer, UnboundedCoverageCountsPixelsBeyondTheBorder) {
  const CameraIntrinsics K = smallCamera();
  // A 1 m square at 2 m covers (fx / 2) x (fy / 2) pixels wherever it is.
  const double expected = (K.fx * 0.5) * (K.fy * 0.5);
  for (const float x : {0.0f, 0.6f, 1.2f}) {  // inside, across the border, outside
    const RenderMesh mesh = square({x, 0, 2}, 1.0f, 1, 0.5f);
    const double area = Rasterizer().unboundedCoverage(mesh, K, Eigen::Isometry3d::Identity(), 1);
    EXPECT_NEAR(area, expected, 0.03 * expected) << x;
  }
}

}  // namespace
}  // namespace pf2
