#include "pf2/surface/mapper.h"

#include <gtest/gtest.h>
#include <octomap/ColorOcTree.h>
#include <octomap/OcTree.h>
#include <pcl/PolygonMesh.h>
#include <pcl/io/obj_io.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "analytic_scene.h"
#include "pf2/core/error.h"

namespace pf2 {
namespace {

using test::AnalyticScene;
using test::lookAt;

AnalyticScene wall() {
  AnalyticScene scene;
  scene.boxes.push_back({Eigen::Vector3d(-3, -3, 2.0), Eigen::Vector3d(3, 3, 2.3)});
  return scene;
}

Eigen::Isometry3d wallPose(int i) {
  return lookAt(Eigen::Vector3d(0.15 * i - 0.2, 0.03 * i, 0.05 * i), Eigen::Vector3d(0.05 * i, 0.0, 2.0));
}

std::string freshDirectory(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / ("pf2_surface_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir.string();
}

TEST(Mapper, CorrectingAWrongKeyframePoseGivesTheMapOfTheRightPoses) {
  const AnalyticScene scene = wall();
  const CameraIntrinsics K;
  Mapper corrected, reference;
  cv::Mat depth, bgr;
  for (int i = 0; i < 3; ++i) {
    scene.render(K, wallPose(i), &depth, &bgr);
    Eigen::Isometry3d wrong = wallPose(i);
    if (i == 2) wrong.pretranslate(Eigen::Vector3d(0.0, 0.0, 0.06));  // tracking put it 6 cm off
    corrected.addKeyframe(i, depth, bgr, K, wrong);
    reference.addKeyframe(i, depth, bgr, K, wallPose(i));
  }
  // Before the correction the third keyframe's wall sits at z = 2.06.
  const TriangleMesh before = corrected.extractMesh();
  double mean_before = 0.0;
  for (const auto& v : before.vertices) mean_before += std::abs(v.z() - 2.0) / before.vertices.size();
  EXPECT_GT(mean_before, 0.004);

  EXPECT_EQ(corrected.updateKeyframePoses({{0, wallPose(0)}, {1, wallPose(1)}, {2, wallPose(2)}, {7, wallPose(0)}}), 1);
  Eigen::Isometry3d stored;
  ASSERT_TRUE(corrected.keyframePose(2, &stored));
  EXPECT_LT((stored.translation() - wallPose(2).translation()).norm(), 1e-12);

  // Same voxels as fusing the right poses in the first place.
  ASSERT_EQ(corrected.tsdf().blockCount(), reference.tsdf().blockCount());
  float worst = 0.f;
  for (const auto& entry : reference.tsdf().blocks()) {
    const auto it = corrected.tsdf().blocks().find(entry.first);
    ASSERT_NE(it, corrected.tsdf().blocks().end());
    for (int i = 0; i < TsdfVolume::kBlockVoxels; ++i) {
      worst = std::max(worst, std::abs(it->second->voxels[i].tsdf - entry.second->voxels[i].tsdf));
      worst = std::max(worst, std::abs(it->second->voxels[i].weight - entry.second->voxels[i].weight));
    }
  }
  EXPECT_LT(worst, 1e-5f);
  const TriangleMesh after = corrected.extractMesh();
  double worst_z = 0.0;
  for (const auto& v : after.vertices) worst_z = std::max(worst_z, std::abs(v.z() - 2.0));
  EXPECT_LT(worst_z, 0.003);

  // The OctoMap is rebuilt at the corrected poses: no wall cells left at z = 2.06.
  OccupancyMap& occupancy = corrected.occupancy();
  int stray = 0, at_wall = 0;
  for (const Eigen::Vector3d& c : occupancy.occupiedCentres()) {
    stray += c.z() > 2.05;
    at_wall += std::abs(c.z() - 2.025) < 0.03;
  }
  EXPECT_EQ(stray, 0);
  EXPECT_GT(at_wall, 100);
}

TEST(Mapper, ReintegrationMovesTheSurface) {
  const AnalyticScene scene = wall();
  const CameraIntrinsics K;
  Mapper mapper;
  cv::Mat depth, bgr;
  scene.render(K, wallPose(0), &depth, &bgr);
  mapper.addKeyframe(0, depth, bgr, K, wallPose(0));
  Eigen::Isometry3d moved = wallPose(0);
  moved.pretranslate(Eigen::Vector3d(0.0, 0.0, -0.10));
  EXPECT_EQ(mapper.updateKeyframePoses({{0, moved}}), 1);
  const TriangleMesh mesh = mapper.extractMesh();
  ASSERT_GT(mesh.vertices.size(), 1000u);
  for (const auto& v : mesh.vertices) ASSERT_NEAR(v.z(), 1.90, 0.003);
  // A pose within the thresholds is not re-fused.
  Eigen::Isometry3d nudged = moved;
  nudged.pretranslate(Eigen::Vector3d(0.0002, 0.0, 0.0));
  EXPECT_EQ(mapper.updateKeyframePoses({{0, nudged}}), 0);
}

TEST(Mapper, KeepsOnlyTheNewestKeyframesWhenAsked) {
  Mapper::Options options;
  options.max_stored_keyframes = 2;
  options.build_occupancy = false;
  Mapper mapper(options);
  const CameraIntrinsics K;
  cv::Mat depth, bgr;
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(mapper.nextToDrop(), i < 2 ? -1 : 10 + i - 2);
    wall().render(K, wallPose(i), &depth, &bgr);
    mapper.addKeyframe(10 + i, depth, bgr, K, wallPose(i));
  }
  EXPECT_EQ(mapper.keyframeCount(), 2u);
  Eigen::Isometry3d T;
  EXPECT_FALSE(mapper.keyframePose(10, &T));
  EXPECT_TRUE(mapper.keyframePose(13, &T));
  EXPECT_EQ(mapper.updateKeyframePoses({{10, wallPose(3)}}), 0);  // frozen
  EXPECT_THROW(mapper.addKeyframe(13, depth, bgr, K, wallPose(0)), Error);
  EXPECT_THROW(mapper.exportMap(freshDirectory("no_octomap")), Error);
}

TEST(Mapper, TheOctoMapHoldsKeyframesWhoseImagesWereDropped) {
  // Filled when read, the OctoMap must still get the keyframes whose images went before: the same
  // cells as a mapper that kept every keyframe, and more than the kept keyframes alone give.
  Mapper::Options bounded_options;
  bounded_options.max_stored_keyframes = 1;
  Mapper bounded(bounded_options), unbounded, newest_only;
  const CameraIntrinsics K;
  cv::Mat depth, bgr;
  for (int i = 0; i < 4; ++i) {
    wall().render(K, wallPose(3 * i), &depth, &bgr);
    bounded.addKeyframe(i, depth, bgr, K, wallPose(3 * i));
    unbounded.addKeyframe(i, depth, bgr, K, wallPose(3 * i));
  }
  newest_only.addKeyframe(3, depth, bgr, K, wallPose(9));
  const std::size_t before = bounded.memoryBytes();
  EXPECT_EQ(bounded.occupancy().occupiedCentres(), unbounded.occupancy().occupiedCentres());
  EXPECT_GT(bounded.occupancy().occupiedCount(), newest_only.occupancy().occupiedCount());
  EXPECT_GT(bounded.memoryBytes(), before);  // the newest keyframe went in when read
}

TEST(Mapper, ExportedFilesReadBackWithPclAndOctomap) {
  AnalyticScene scene;
  scene.has_room = true;
  scene.room = {Eigen::Vector3d(-1.5, -1.2, -1.5), Eigen::Vector3d(1.5, 1.0, 1.5)};
  const CameraIntrinsics K;
  Mapper mapper;
  cv::Mat depth, bgr;
  for (int i = 0; i < 4; ++i) {
    const double angle = i * M_PI / 2;
    const Eigen::Vector3d p_w(0.2 * std::cos(angle), -0.1, 0.2 * std::sin(angle));
    const Eigen::Isometry3d T_w_c = lookAt(p_w, p_w + Eigen::Vector3d(std::cos(angle), 0.2, std::sin(angle)));
    scene.render(K, T_w_c, &depth, &bgr);
    mapper.addKeyframe(i, depth, bgr, K, T_w_c);
  }
  const std::string dir = freshDirectory("export");
  Mapper::ExportOptions all;
  all.points_pcd = true;
  all.mesh_obj = true;
  mapper.exportMap(dir, all);
  const TriangleMesh mesh = mapper.extractMesh();

  pcl::PolygonMesh ply;
  ASSERT_EQ(pcl::io::loadPLYFile(dir + "/map.ply", ply), 0);
  ASSERT_EQ(ply.polygons.size(), mesh.triangles.size());
  pcl::PointCloud<pcl::PointXYZRGB> ply_points;
  pcl::fromPCLPointCloud2(ply.cloud, ply_points);
  ASSERT_EQ(ply_points.size(), mesh.vertices.size());
  for (std::size_t i = 0; i < ply_points.size(); i += 97) {
    EXPECT_LT(scene.distance(ply_points[i].getVector3fMap().cast<double>()), 0.005);
    EXPECT_EQ(ply_points[i].r, mesh.colors[i][0]);
    EXPECT_EQ(ply_points[i].b, mesh.colors[i][2]);
  }
  const TriangleMesh reloaded = loadMeshPly(dir + "/map.ply");
  EXPECT_NEAR(reloaded.area(), mesh.area(), 1e-6 * mesh.area());

  // The OBJ: one `v x y z r g b` line per vertex (colour 0..1) and one 1-based `f` per triangle.
  pcl::PolygonMesh obj;
  ASSERT_EQ(pcl::io::loadOBJFile(dir + "/map.obj", obj), 0);
  ASSERT_EQ(obj.polygons.size(), mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); i += 101) {
    for (int k = 0; k < 3; ++k) EXPECT_EQ(obj.polygons[i].vertices[k], static_cast<std::uint32_t>(mesh.triangles[i][k]));
  }
  pcl::PointCloud<pcl::PointXYZ> obj_points;
  pcl::fromPCLPointCloud2(obj.cloud, obj_points);
  ASSERT_EQ(obj_points.size(), mesh.vertices.size());
  for (std::size_t i = 0; i < obj_points.size(); i += 97) {
    EXPECT_LT((obj_points[i].getVector3fMap() - mesh.vertices[i]).norm(), 1e-5f);
  }
  std::ifstream obj_text(dir + "/map.obj");
  std::string line;
  while (std::getline(obj_text, line) && line.rfind("v ", 0) != 0) {
  }
  std::istringstream first_vertex(line.substr(2));
  float x = 0, y = 0, z = 0, r = 0, g = 0, b = 0;
  ASSERT_TRUE(static_cast<bool>(first_vertex >> x >> y >> z >> r >> g >> b)) << line;
  EXPECT_NEAR(r, mesh.colors[0][0] / 255.0f, 1e-3f);
  EXPECT_NEAR(b, mesh.colors[0][2] / 255.0f, 1e-3f);

  octomap::OcTree tree(0.1);
  ASSERT_TRUE(tree.readBinary(dir + "/map.bt"));
  EXPECT_DOUBLE_EQ(tree.getResolution(), 0.05);
  int occupied = 0;
  for (auto it = tree.begin_leafs(), end = tree.end_leafs(); it != end; ++it) {
    if (!tree.isNodeOccupied(*it)) continue;
    ++occupied;
    const Eigen::Vector3d c(it.getX(), it.getY(), it.getZ());
    EXPECT_LT(scene.distance(c), 0.5 * it.getSize() * std::sqrt(3.0) + 1e-6) << c.transpose();
  }
  EXPECT_GT(occupied, 500);
  // The room's middle is free space.
  const octomap::OcTreeNode* middle = tree.search(0.0, 0.0, 0.8);
  ASSERT_NE(middle, nullptr);
  EXPECT_FALSE(tree.isNodeOccupied(middle));

  std::unique_ptr<octomap::AbstractOcTree> coloured(octomap::AbstractOcTree::read(dir + "/map.ot"));
  ASSERT_NE(coloured, nullptr);
  EXPECT_NE(dynamic_cast<octomap::ColorOcTree*>(coloured.get()), nullptr);

  pcl::PointCloud<pcl::PointXYZRGB> pcd;
  ASSERT_EQ(pcl::io::loadPCDFile(dir + "/map.pcd", pcd), 0);
  EXPECT_EQ(pcd.size(), mesh.vertices.size());

  // Nothing but the five files: no temporary left behind.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(entry.path().stem().string(), "map") << entry.path();
  }
  EXPECT_EQ(files, 5);
}

TEST(Mapper, UnwritableOutputNamesTheFile) {
  Mapper mapper;
  const CameraIntrinsics K;
  cv::Mat depth, bgr;
  wall().render(K, wallPose(0), &depth, &bgr);
  mapper.addKeyframe(0, depth, bgr, K, wallPose(0));
  const std::string missing = freshDirectory("unwritable") + "/no/such/dir";
  const auto message = [&](const Mapper::ExportOptions& what) {
    try {
      mapper.exportMap(missing, what);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  Mapper::ExportOptions ply_only{true, false, false, false}, bt_only{false, true, false, false},
      pcd_only{false, false, false, true};
  EXPECT_NE(message(ply_only).find(missing + "/map.ply"), std::string::npos) << message(ply_only);
  EXPECT_NE(message(bt_only).find(missing + "/map.bt"), std::string::npos) << message(bt_only);
  EXPECT_NE(message(pcd_only).find(missing + "/map.pcd"), std::string::npos) << message(pcd_only);
  EXPECT_THROW(loadMeshPly(missing + "/map.ply"), Error);
}

}  // namespace
}  // namespace pf2
