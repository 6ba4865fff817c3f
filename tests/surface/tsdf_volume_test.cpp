#include "pf2/surface/tsdf_volume.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "analytic_scene.h"
#include "pf2/core/error.h"
#include "pf2/surface/marching_cubes.h"

namespace pf2 {
namespace {

using test::AnalyticScene;
using test::boxRoom;
using test::lookAt;

std::vector<Eigen::Isometry3d> roomPoses() {
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < 8; ++i) {
    const double angle = i * M_PI / 4;
    const Eigen::Vector3d p_w(0.3 * std::cos(angle), -0.1, 0.3 * std::sin(angle));
    poses.push_back(lookAt(p_w, p_w + Eigen::Vector3d(std::cos(angle), 0.15, std::sin(angle))));
  }
  return poses;
}

TEST(MarchingCubesTable, EveryCrossedEdgeIsUsedAndNoOther) {
  for (int c = 1; c < 255; ++c) {
    std::array<int, 12> uses{};
    for (const auto& t : marching_cubes::triangles(c)) {
      for (int e : t) ++uses[e];
    }
    for (int e = 0; e < 12; ++e) {
      const bool crossed = ((c >> marching_cubes::kEdgeCorners[e][0]) & 1) != ((c >> marching_cubes::kEdgeCorners[e][1]) & 1);
      EXPECT_EQ(crossed, uses[e] > 0) << "case " << c << " edge " << e;
    }
  }
  EXPECT_TRUE(marching_cubes::triangles(0).empty());
  EXPECT_TRUE(marching_cubes::triangles(255).empty());
}

TEST(MarchingCubesTable, TrianglesFaceTheOutside) {
  // Corners with z = 0 inside (bits 0..3): the surface is a horizontal square facing +z.
  const auto& triangles = marching_cubes::triangles(0x0F);
  ASSERT_EQ(triangles.size(), 2u);
  const auto midpoint = [](int e) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int k = 0; k < 2; ++k) {
      const int c = marching_cubes::kEdgeCorners[e][k];
      p += 0.5 * Eigen::Vector3d(c & 1, (c >> 1) & 1, (c >> 2) & 1);
    }
    return p;
  };
  for (const auto& t : triangles) {
    const Eigen::Vector3d n = (midpoint(t[1]) - midpoint(t[0])).cross(midpoint(t[2]) - midpoint(t[0]));
    EXPECT_GT(n.z(), 0.0);
  }
}

TEST(TsdfVolume, PlaneFromSeveralPosesLiesOnTheTrueSurface) {
  AnalyticScene scene;
  scene.boxes.push_back({Eigen::Vector3d(-3, -3, 2.0), Eigen::Vector3d(3, 3, 2.5)});  // wall z = 2
  const CameraIntrinsics K;
  TsdfVolume volume;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d p_w(0.2 * i - 0.3, 0.05 * i, 0.1 * i);
    cv::Mat depth, bgr;
    const Eigen::Isometry3d T_w_c = lookAt(p_w, Eigen::Vector3d(0.1 * i, 0, 2.0));
    scene.render(K, T_w_c, &depth, &bgr);
    volume.integrate(depth, bgr, K, T_w_c);
  }
  const TriangleMesh mesh = volume.extractMesh();
  ASSERT_GT(mesh.vertices.size(), 10000u);
  ASSERT_EQ(mesh.colors.size(), mesh.vertices.size());
  double worst = 0.0;
  for (const auto& v : mesh.vertices) worst = std::max(worst, std::abs(v.z() - 2.0));
  EXPECT_LT(worst, 0.003);
  // About a 2 m x 1.5 m patch of the wall is in view at 2 m.
  EXPECT_GT(mesh.area(), 2.5);
  // Triangles face the camera (-z).
  Eigen::Vector3d normal_sum = Eigen::Vector3d::Zero();
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d a = mesh.vertices[t[0]].cast<double>(), b = mesh.vertices[t[1]].cast<double>(),
                          c = mesh.vertices[t[2]].cast<double>();
    normal_sum += (b - a).cross(c - a);
  }
  EXPECT_LT(normal_sum.normalized().z(), -0.99);
}

TEST(TsdfVolume, BoxRoomMeshIsWithinMillimetresOfTheWalls) {
  const AnalyticScene scene = boxRoom();
  const CameraIntrinsics K;
  TsdfVolume volume;
  for (const auto& T_w_c : roomPoses()) {
    cv::Mat depth, bgr;
    scene.render(K, T_w_c, &depth, &bgr);
    volume.integrate(depth, bgr, K, T_w_c);
  }
  const TriangleMesh mesh = volume.extractMesh();
  ASSERT_GT(mesh.vertices.size(), 50000u);
  std::vector<double> distances;
  for (const auto& v : mesh.vertices) distances.push_back(scene.distance(v.cast<double>()));
  std::sort(distances.begin(), distances.end());
  double mean = 0.0;
  for (double d : distances) mean += d / distances.size();
  EXPECT_LT(mean, 0.002);
  EXPECT_LT(distances[distances.size() * 99 / 100], 0.005);
  // Colours come from the checkerboard: every vertex is one of the two colours or a blend.
  int blue_or_orange = 0;
  for (const auto& c : mesh.colors) blue_or_orange += (c[0] == 30 && c[2] == 200) || (c[0] == 220 && c[2] == 40);
  EXPECT_GT(blue_or_orange, static_cast<int>(mesh.colors.size() / 2));
}

TEST(TsdfVolume, DeintegrationExactlyUndoesIntegration) {
  const AnalyticScene scene = boxRoom();
  const CameraIntrinsics K;
  TsdfVolume volume;
  const auto poses = roomPoses();
  cv::Mat depth, bgr;
  for (int i = 0; i < 3; ++i) {
    scene.render(K, poses[i], &depth, &bgr);
    volume.integrate(depth, bgr, K, poses[i]);
  }
  std::map<std::array<int, 3>, TsdfVolume::Block> before;
  for (const auto& entry : volume.blocks()) before[{entry.first.x(), entry.first.y(), entry.first.z()}] = *entry.second;

  // A frame overlapping the others, seen from a nudged pose, in and out again.
  Eigen::Isometry3d T_w_c = poses[1];
  T_w_c.translate(Eigen::Vector3d(0.013, -0.021, 0.034));
  T_w_c.rotate(Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitY()));
  scene.render(K, T_w_c, &depth, &bgr);
  volume.integrate(depth, bgr, K, T_w_c);
  EXPECT_GT(volume.blockCount(), before.size());
  volume.deintegrate(depth, bgr, K, T_w_c);

  ASSERT_EQ(volume.blockCount(), before.size());
  float worst_tsdf = 0.f, worst_weight = 0.f, worst_colour = 0.f;
  for (const auto& entry : volume.blocks()) {
    const auto it = before.find({entry.first.x(), entry.first.y(), entry.first.z()});
    ASSERT_NE(it, before.end());
    for (int i = 0; i < TsdfVolume::kBlockVoxels; ++i) {
      const auto& a = entry.second->voxels[i];
      const auto& b = it->second.voxels[i];
      worst_tsdf = std::max(worst_tsdf, std::abs(a.tsdf - b.tsdf));
      worst_weight = std::max(worst_weight, std::abs(a.weight - b.weight));
      worst_colour = std::max(worst_colour, std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b));
    }
  }
  EXPECT_LT(worst_tsdf, 1e-5f);
  EXPECT_LT(worst_weight, 1e-5f);
  EXPECT_LT(worst_colour, 1e-3f);
}

TEST(TsdfVolume, RemovedPersonDepthLeavesNoSurface) {
  AnalyticScene empty = boxRoom();
  AnalyticScene with_person = empty;
  const test::Box person{Eigen::Vector3d(-0.25, -0.5, 1.0), Eigen::Vector3d(0.25, 1.2, 1.3)};
  with_person.boxes.push_back(person);
  const CameraIntrinsics K;
  TsdfVolume volume;
  for (int i = 0; i < 3; ++i) {
    const Eigen::Isometry3d T_w_c = lookAt(Eigen::Vector3d(0.2 * i, -0.2, -1.0), Eigen::Vector3d(0, 0, 1.5));
    cv::Mat depth, depth_empty, bgr;
    with_person.render(K, T_w_c, &depth, &bgr);
    empty.render(K, T_w_c, &depth_empty);
    // The person mask: pixels whose depth the person changed; their depth is removed (0).
    cv::Mat mask = cv::abs(depth - depth_empty) > 1e-4f;
    ASSERT_GT(cv::countNonZero(mask), 10000);
    depth.setTo(0.f, mask);
    volume.integrate(depth, bgr, K, T_w_c);
  }
  const TriangleMesh mesh = volume.extractMesh();
  ASSERT_GT(mesh.vertices.size(), 10000u);
  int near_person = 0, off_surface = 0;
  for (const auto& v : mesh.vertices) {
    near_person += AnalyticScene::boxDistance(person, v.cast<double>()) < 0.03 &&
                   empty.distance(v.cast<double>()) > 0.03;
    off_surface += empty.distance(v.cast<double>()) > 0.01;
  }
  EXPECT_EQ(near_person, 0);
  EXPECT_EQ(off_surface, 0);
}

TEST(TsdfVolume, RejectsMismatchedImages) {
  TsdfVolume volume;
  const CameraIntrinsics K;
  cv::Mat depth(240, 320, CV_32F, cv::Scalar(1.0f));
  EXPECT_THROW(volume.integrate(depth, cv::Mat(), K, Eigen::Isometry3d::Identity()), Error);
  cv::Mat depth16(480, 640, CV_16U, cv::Scalar(5000));
  EXPECT_THROW(volume.integrate(depth16, cv::Mat(), K, Eigen::Isometry3d::Identity()), Error);
  TsdfVolume::Options bad;
  bad.voxel_size = 0;
  EXPECT_THROW(TsdfVolume{bad}, Error);
}

TEST(TsdfVolume, FarBlocksCanBeDropped) {
  const AnalyticScene scene = boxRoom();
  const CameraIntrinsics K;
  TsdfVolume volume;
  cv::Mat depth;
  const Eigen::Isometry3d T_w_c = roomPoses()[0];
  scene.render(K, T_w_c, &depth);
  volume.integrate(depth, cv::Mat(), K, T_w_c);
  const std::size_t all = volume.blockCount();
  const std::size_t bytes = volume.memoryBytes();
  EXPECT_GT(bytes, all * sizeof(TsdfVolume::Block));
  const std::size_t removed = volume.removeBlocksFartherThan(T_w_c.translation(), 2.0);
  EXPECT_GT(removed, 0u);
  EXPECT_EQ(volume.blockCount(), all - removed);
  for (const auto& entry : volume.blocks()) {
    const Eigen::Vector3d centre = (entry.first.cast<double>() * 8 + Eigen::Vector3d::Constant(3.5)) * 0.01;
    EXPECT_LE((centre - T_w_c.translation()).norm(), 2.0);
  }
}

}  // namespace
}  // namespace pf2
