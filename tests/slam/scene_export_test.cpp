// scene.ply / scene.obj: the map with each person's body and track, read back through PCL.
#include <fstream>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "pf2/slam/scene_export.h"

namespace pf2 {
namespace {

const BodyModel& model() {
  static const BodyModel loaded = BodyModel::loadDefault();
  return loaded;
}

// A floor of two triangles, grey-blue.
TriangleMesh floorMesh() {
  TriangleMesh mesh;
  mesh.vertices = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}};
  mesh.colors.assign(4, {90, 100, 140});
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  return mesh;
}

// A track of `frames` standing bodies walking along x; the last one fitted.
BodyTrack walkingTrack(int id, int frames, double y) {
  BodyTrack track;
  track.id = id;
  track.shape = Eigen::VectorXd::Zero(10);
  for (int i = 0; i < frames; ++i) {
    BodyTrackFrame frame;
    frame.timestamp = i / 30.0;
    frame.fitted = i == frames - 1;
    frame.body_w.pose[0] = Eigen::Vector3d(M_PI / 2, 0, 0);  // body y up -> world z up
    frame.body_w.translation = Eigen::Vector3d(0.05 * i, y, 1.0) - model().restJoints(track.shape)[0];
    frame.joints_w = model().posedJoints(frame.body_w);
    frame.pelvis_w = frame.joints_w[0];
    track.frames.push_back(frame);
  }
  return track;
}

std::array<std::uint8_t, 3> bytes(int id) {
  const auto c = personColour(id);
  return {static_cast<std::uint8_t>(std::lround(255 * c[0])), static_cast<std::uint8_t>(std::lround(255 * c[1])),
          static_cast<std::uint8_t>(std::lround(255 * c[2]))};
}

TEST(SceneExport, MapBodiesAndTracksReadBackThroughPclWithOneColourPerId) {
  const std::vector<BodyTrack> tracks = {walkingTrack(1, 10, 1.0), walkingTrack(2, 6, 2.5)};
  const int body_vertices = model().vertexCount();
  const std::string ply = testing::TempDir() + "pf2_scene.ply";
  const std::string obj = testing::TempDir() + "pf2_scene.obj";

  // Default: each person's last fitted body and their track.
  const TriangleMesh scene = buildScene(floorMesh(), tracks, model(), SceneOptions());
  saveMeshPly(scene, ply);
  saveMeshObj(scene, obj);
  const TriangleMesh read = loadMeshPly(ply);
  ASSERT_EQ(read.vertices.size(), 4u + 2u * body_vertices + 10u + 6u);
  EXPECT_EQ(read.triangles.size(), 2u + 2u * model().triangles().size());
  std::map<std::array<std::uint8_t, 3>, int> per_colour;
  for (const auto& c : read.colors) ++per_colour[c];
  EXPECT_EQ(per_colour[bytes(1)], body_vertices + 10);
  EXPECT_EQ(per_colour[bytes(2)], body_vertices + 6);
  EXPECT_EQ(per_colour[(std::array<std::uint8_t, 3>{90, 100, 140})], 4);
  // The PLY's edge element and the OBJ's lines: one segment per step of each track.
  EXPECT_EQ(scene.edges.size(), 9u + 5u);
  std::ifstream obj_in(obj);
  std::string line;
  int lines = 0, vertices = 0;
  while (std::getline(obj_in, line)) {
    lines += line.rfind("l ", 0) == 0;
    vertices += line.rfind("v ", 0) == 0;
  }
  EXPECT_EQ(lines, 14);
  EXPECT_EQ(vertices, static_cast<int>(read.vertices.size()));
  // Track 1 comes after the map and its body: its last point is its pelvis at the end.
  const Eigen::Vector3f last_pelvis = tracks[0].frames.back().pelvis_w.cast<float>();
  EXPECT_LT((read.vertices[4 + body_vertices + 9] - last_pelvis).norm(), 1e-6);

  // Every 4th body along the tracks too: frames 0, 4, 8 and 9 of track 1, 0, 4 and 5 of track 2.
  SceneOptions every;
  every.bodies_every = 4;
  const TriangleMesh more = buildScene(TriangleMesh(), tracks, model(), every);
  EXPECT_EQ(more.vertices.size(), 7u * body_vertices + 16u);
}

}  // namespace
}  // namespace pf2
