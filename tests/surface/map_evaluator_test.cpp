#include "pf2/surface/map_evaluator.h"

#include <gtest/gtest.h>

#include <random>

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

}  // namespace
}  // namespace pf2
