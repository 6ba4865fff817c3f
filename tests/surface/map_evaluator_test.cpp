#include "pf2/surface/map_evaluator.h"

#include <gtest/gtest.h>

#include <array>
#include <random>
#include <string>

#include "analytic_scene.h"
#include "pf2/surface/tsdf_volume.h"

namespace pf2 {
namespace {

TEST(PointTriangleDistance, AllRegions) {
  const Eigen::Vector3d a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  EXPECT_NEAR(pointTriangleDistance({0.2, 0.2, 0.5}, a, b, c), 0.5, 1e-12);     // face
  EXPECT_NEAR(pointTriangleDistance({-1, -1, 0}, a, b, c), std::sqrt(2.0), 1e-12);  // vertex a
  EXPECT_NEAR(pointTriangleDistance({2, 0, 1}, a, b, c), std::sqrt(2.0), 1e-12);    // vertex b
  EXPECT_NEAR(pointTriangleDistance({0.5, -2, 0}, a, b, c), 2.0, 1e-12);            // edge ab
  EXPECT_NEAR(pointTriangleDistance({1, 1, 0}, a, b, c), std::sqrt(0.5), 1e-12);    // edge bc
  EXPECT_NEAR(pointTriangleDistance({-3, 0.5, 4}, a, b, c), 5.0, 1e-12);            // edge ca
}

TEST(MeshDistance, MatchesBruteForceAndCaps) {
  const test::Box box{Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 0.5, 2)};
  const TriangleMesh mesh = test::boxMesh(box);
  const MeshDistance field(mesh, 0.2, 0.05);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> coordinate(-1.3, 2.3);
  int near = 0;
  for (int i = 0; i < 3000; ++i) {
    const Eigen::Vector3d p(coordinate(random), coordinate(random), coordinate(random));
    double brute = 1e9;
    for (const auto& t : mesh.triangles) {
      brute = std::min(brute, pointTriangleDistance(p, mesh.vertices[t[0]].cast<double>(),
                                                    mesh.vertices[t[1]].cast<double>(), mesh.vertices[t[2]].cast<double>()));
    }
    EXPECT_NEAR(field.distance(p), std::min(brute, 0.2), 1e-9) << p.transpose();
    near += brute < 0.2;
  }
  EXPECT_GT(near, 300);
}

TEST(MapEvaluator, ScoresAnOffsetMapAGhostAndAHole) {
  const test::Box room{Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)};
  const TriangleMesh truth = test::boxMesh(room);
  MapEvaluator::Options options;
  options.sample_spacing = 0.02;
  MapEvaluator evaluator(truth, options);
  evaluator.markAllSeen();

  // The map: the room shrunk by 5 mm on every side (all faces 5 mm off), minus the floor (y = 1),
  // plus a 'ghost' triangle in the middle.
  const test::Box shrunk{Eigen::Vector3d::Constant(-0.995), Eigen::Vector3d::Constant(0.995)};
  TriangleMesh map = test::boxMesh(shrunk);
  map.triangles.erase(map.triangles.begin() + 6, map.triangles.begin() + 8);  // quad {2,3,7,6}: y max
  const int ghost = static_cast<int>(map.vertices.size());
  map.vertices.emplace_back(0.f, 0.f, 0.f);
  map.vertices.emplace_back(0.1f, 0.f, 0.f);
  map.vertices.emplace_back(0.f, 0.1f, 0.f);
  map.triangles.emplace_back(ghost, ghost + 1, ghost + 2);

  const MapQuality q = evaluator.evaluate(map);
  EXPECT_EQ(q.map_vertices, 11u);
  EXPECT_EQ(q.ghost_vertices, 3u);
  EXPECT_NEAR(q.median, 0.005, 1e-6);  // every vertex is 5 mm from its nearest wall
  EXPECT_NEAR(q.max, options.max_distance, 1e-9);        // the ghost is capped
  EXPECT_GT(q.seen_samples, 10000u);
  EXPECT_NEAR(q.completeness, 5.0 / 6.0, 0.02);          // one face of six is missing
}

TEST(MapEvaluator, OnlySeenSurfaceCountsForCompleteness) {
  const test::Box room{Eigen::Vector3d(-1.5, -1.5, -1.5), Eigen::Vector3d(1.5, 1.5, 1.5)};
  test::AnalyticScene scene;
  scene.has_room = true;
  scene.room = room;
  MapEvaluator::Options options;
  options.sample_spacing = 0.02;
  MapEvaluator evaluator(test::boxMesh(room), options);
  const CameraIntrinsics K;
  const Eigen::Isometry3d T_w_c = test::lookAt(Eigen::Vector3d(0, 0, -0.5), Eigen::Vector3d(0, 0, 1.5));
  cv::Mat depth;
  scene.render(K, T_w_c, &depth);
  evaluator.markSeen(depth, K, T_w_c);
  TsdfVolume volume;
  volume.integrate(depth, cv::Mat(), K, T_w_c);
  const MapQuality q = evaluator.evaluate(volume.extractMesh());
  // The view covers less than a sixth of the room...
  EXPECT_LT(q.seen_samples, evaluator.sampleCount() / 6);
  EXPECT_GT(q.seen_samples, 1000u);
  // ...and the map made from that view covers nearly all of what it saw, within millimetres.
  EXPECT_GT(q.completeness, 0.95);
  EXPECT_LT(q.mean, 0.002);
  EXPECT_EQ(q.ghost_vertices, 0u);
}

// Two 0.2 m square walls facing the camera, one at 2 m and one at 3.2 m; the map holds only the
// near one. Every sample lands in the range bin of the depth it was first seen at, and a later,
// farther view does not move it.
TEST(MapEvaluator, CompletenessByRangeAndIncidence) {
  const auto quad = [](TriangleMesh* mesh, float x0, float x1, float z) {
    const int base = static_cast<int>(mesh->vertices.size());
    mesh->vertices.emplace_back(x0, -0.1f, z);
    mesh->vertices.emplace_back(x1, -0.1f, z);
    mesh->vertices.emplace_back(x1, 0.1f, z);
    mesh->vertices.emplace_back(x0, 0.1f, z);
    mesh->triangles.emplace_back(base, base + 2, base + 1);
    mesh->triangles.emplace_back(base, base + 3, base + 2);
  };
  TriangleMesh truth, map;
  quad(&truth, -0.3f, -0.1f, 2.0f);
  quad(&truth, 0.1f, 0.3f, 3.2f);
  quad(&map, -0.3f, -0.1f, 2.0f);
  MapEvaluator evaluator(truth, MapEvaluator::Options());
  const std::size_t per_wall = evaluator.sampleCount() / 2;
  ASSERT_EQ(evaluator.sampleCount(), 2 * per_wall);

  // Depth of the two walls (each drawn 5 cm larger, so that no sample falls off its edge).
  const CameraIntrinsics K;
  const auto depth_from = [&](double camera_z) {
    cv::Mat depth(K.height, K.width, CV_32F, cv::Scalar(0.f));
    for (int v = 0; v < K.height; ++v) {
      for (int u = 0; u < K.width; ++u) {
        const double rx = (u - K.cx) / K.fx, ry = (v - K.cy) / K.fy;
        for (const auto& [x0, x1, z] :
             {std::array<double, 3>{-0.35, -0.05, 2.0}, std::array<double, 3>{0.05, 0.35, 3.2}}) {
          const double d = z - camera_z;
          if (rx * d >= x0 && rx * d <= x1 && std::abs(ry * d) <= 0.15) depth.at<float>(v, u) = static_cast<float>(d);
        }
      }
    }
    return depth;
  };
  evaluator.markSeen(depth_from(0.0), K, Eigen::Isometry3d::Identity());
  Eigen::Isometry3d back = Eigen::Isometry3d::Identity();
  back.translation().z() = -0.6;  // the far wall is now 3.8 m away, the near one 2.6 m
  evaluator.markSeen(depth_from(-0.6), K, back);

  const MapQuality q = evaluator.evaluate(map);
  EXPECT_EQ(q.seen_samples, 2 * per_wall);
  EXPECT_DOUBLE_EQ(q.completeness, 0.5);
  // Bins of 0.5 m from 0: the near wall in [2.0, 2.5), the far one in [3.0, 3.5).
  ASSERT_EQ(q.by_range.size(), 7u);
  for (std::size_t k = 0; k < q.by_range.size(); ++k) {
    EXPECT_DOUBLE_EQ(q.by_range[k].lower, 0.5 * k);
    EXPECT_DOUBLE_EQ(q.by_range[k].upper, 0.5 * (k + 1));
    const std::size_t seen = (k == 4 || k == 6) ? per_wall : 0;
    EXPECT_EQ(q.by_range[k].seen, seen) << k;
    EXPECT_EQ(q.by_range[k].covered, k == 4 ? per_wall : 0u) << k;
  }
  // Both walls face the camera within atan(0.32 / 2) = 9 degrees: all in the first 15 degree bin.
  ASSERT_EQ(q.by_incidence.size(), 1u);
  EXPECT_EQ(q.by_incidence[0].seen, 2 * per_wall);
  EXPECT_EQ(q.by_incidence[0].covered, per_wall);
  EXPECT_EQ(completenessBreakdown(q),
            "  nearest view 2.0-2.5 m: 100.0 % of " + std::to_string(per_wall) + " seen samples\n" +
            "  nearest view 3.0-3.5 m: 0.0 % of " + std::to_string(per_wall) + " seen samples\n" +
            "  incidence 0-15 deg: 50.0 % of " + std::to_string(2 * per_wall) + " seen samples\n");
}

}  // namespace
}  // namespace pf2
