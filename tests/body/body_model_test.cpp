#include "pf2/body/body_model.h"

#include <pcl/PolygonMesh.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "pf2/body/body_mesh_io.h"
#include "pf2/body/npy.h"
#include "pf2/core/error.h"

namespace pf2 {
namespace {

// A tiny SMPL-format model. Vertices 0..23 sit on the joints (the regressor is the identity on
// them, so joint j is vertex j); they are skinned to the pelvis. Three more vertices:
//   kForearm: (0.7, 0, 0), all weight on the left elbow, which sits at (0.5, 0, 0);
//   kSplit:   (0.5, 0.1, 0), half left shoulder (0.2, 0, 0), half left elbow;
//   kShaped:  (0, -1, 0), pelvis; shape direction 0 moves it by (0, 0, 0.1) and the left elbow
//             joint vertex by (0.1, 0, 0).
constexpr double kPi = 3.14159265358979323846;
constexpr int kForearm = 24, kSplit = 25, kShaped = 26, kVertices = 27;

struct TinyModel {
  std::vector<float> v_template, shapedirs, posedirs, regressor, weights;
  std::vector<std::int32_t> kintree, faces;
  int shape_count = 2;

  TinyModel() {
    v_template.assign(3 * kVertices, 0.0f);
    auto set = [&](int v, float x, float y, float z) {
      v_template[3 * v] = x;
      v_template[3 * v + 1] = y;
      v_template[3 * v + 2] = z;
    };
    for (int j = 0; j < kBodyJointCount; ++j) set(j, 0.01f * j, 0.02f * j, 0.0f);
    set(16, 0.2f, 0, 0);   // left shoulder
    set(18, 0.5f, 0, 0);   // left elbow
    set(20, 0.8f, 0, 0);   // left wrist
    set(kForearm, 0.7f, 0, 0);
    set(kSplit, 0.5f, 0.1f, 0);
    set(kShaped, 0, -1, 0);
    shapedirs.assign(3 * kVertices * shape_count, 0.0f);
    shapedirs[(3 * kShaped + 2) * shape_count + 0] = 0.1f;
    shapedirs[(3 * 18 + 0) * shape_count + 0] = 0.1f;
    posedirs.assign(3 * kVertices * 207, 0.0f);
    regressor.assign(kBodyJointCount * kVertices, 0.0f);
    for (int j = 0; j < kBodyJointCount; ++j) regressor[j * kVertices + j] = 1.0f;
    weights.assign(kVertices * kBodyJointCount, 0.0f);
    for (int v = 0; v < kVertices; ++v) weights[v * kBodyJointCount] = 1.0f;
    weights[kForearm * kBodyJointCount] = 0.0f;
    weights[kForearm * kBodyJointCount + 18] = 1.0f;
    weights[kSplit * kBodyJointCount] = 0.0f;
    weights[kSplit * kBodyJointCount + 16] = 0.5f;
    weights[kSplit * kBodyJointCount + 18] = 0.5f;
    for (int j = 0; j < kBodyJointCount; ++j) {
      kintree.push_back(kBodyJointParents[j]);
    }
    for (int j = 0; j < kBodyJointCount; ++j) kintree.push_back(j);
    faces = {kForearm, kSplit, kShaped, 0, 1, 2};
  }

  std::vector<std::pair<std::string, NpyArray>> arrays() const {
    const std::size_t V = kVertices, B = static_cast<std::size_t>(shape_count);
    return {{"v_template", NpyArray::fromFloats({V, 3}, v_template)},
            {"shapedirs", NpyArray::fromFloats({V, 3, B}, shapedirs)},
            {"posedirs", NpyArray::fromFloats({V, 3, 207}, posedirs)},
            {"J_regressor", NpyArray::fromFloats({kBodyJointCount, V}, regressor)},
            {"weights", NpyArray::fromFloats({V, kBodyJointCount}, weights)},
            {"kintree_table", NpyArray::fromInt32({2, kBodyJointCount}, kintree)},
            {"f", NpyArray::fromInt32({faces.size() / 3, 3}, faces)}};
  }

  std::string write(const std::string& name) const {
    const std::string path = testing::TempDir() + name;
    writeNpz(path, arrays());
    return path;
  }
};

Eigen::Vector3d at(const BodyMesh& mesh, int v) { return mesh.vertices[v].cast<double>(); }

// Replaces one array of `arrays`.
void replace(std::vector<std::pair<std::string, NpyArray>>* arrays, const std::string& name, NpyArray array) {
  for (auto& [n, a] : *arrays) {
    if (n == name) a = std::move(array);
  }
}

void expectLoadError(const std::vector<std::pair<std::string, NpyArray>>& arrays, const std::string& name,
                     const std::vector<std::string>& parts) {
  const std::string path = testing::TempDir() + "pf2_tiny_broken_" + name + ".npz";
  writeNpz(path, arrays);
  try {
    BodyModel::loadNpz(path);
    FAIL() << "no error for " << name;
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    for (const auto& part : parts) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(BodyModel, JointTableIsSmpl) {
  EXPECT_STREQ(kBodyJointNames[0], "pelvis");
  EXPECT_STREQ(kBodyJointNames[18], "left_elbow");
  EXPECT_STREQ(kBodyJointNames[23], "right_hand");
  EXPECT_EQ(kBodyJointParents[0], -1);
  for (int j = 1; j < kBodyJointCount; ++j) EXPECT_LT(kBodyJointParents[j], j);  // parents come first
  EXPECT_EQ(kBodyJointParents[15], 12);  // head <- neck
  EXPECT_EQ(kBodyJointParents[20], 18);  // left wrist <- left elbow
}

TEST(BodyModel, RestPoseIsTheTemplate) {
  const TinyModel tiny;
  const BodyModel model = BodyModel::loadNpz(tiny.write("pf2_tiny_rest.npz"));
  EXPECT_EQ(model.vertexCount(), kVertices);
  EXPECT_EQ(model.shapeCount(), 2);
  EXPECT_FALSE(model.hasPoseBlendShapes());  // all-zero posedirs
  BodyParameters p;
  p.translation = Eigen::Vector3d(1, 2, 3);
  const BodyMesh mesh = model.evaluate(p);
  ASSERT_EQ(mesh.vertices.size(), static_cast<std::size_t>(kVertices));
  for (int v = 0; v < kVertices; ++v) {
    const Eigen::Vector3d expected(tiny.v_template[3 * v] + 1.0, tiny.v_template[3 * v + 1] + 2.0,
                                   tiny.v_template[3 * v + 2] + 3.0);
    EXPECT_NEAR((at(mesh, v) - expected).norm(), 0.0, 1e-6) << v;
  }
  EXPECT_NEAR((mesh.joints[18] - Eigen::Vector3d(1.5, 2, 3)).norm(), 0.0, 1e-6);
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.triangles[0], Eigen::Vector3i(kForearm, kSplit, kShaped));
  for (int v = 0; v < kVertices; ++v) EXPECT_NEAR(model.weights().row(v).sum(), 1.0f, 1e-6f);
}

TEST(BodyModel, ElbowBendOf90DegreesMovesTheForearmExactly) {
  const BodyModel model = BodyModel::loadNpz(TinyModel().write("pf2_tiny_elbow.npz"));
  BodyParameters p;
  p.pose[18] = Eigen::Vector3d(0, 0, kPi / 2);  // left elbow, +90 degrees about z: x -> y
  const BodyMesh mesh = model.evaluate(p);
  // Forearm vertex 0.2 m beyond the elbow now points along +y.
  EXPECT_NEAR((at(mesh, kForearm) - Eigen::Vector3d(0.5, 0.2, 0)).norm(), 0.0, 1e-6);
  EXPECT_NEAR((mesh.joints[20] - Eigen::Vector3d(0.5, 0.3, 0)).norm(), 0.0, 1e-6);  // wrist
  EXPECT_NEAR((mesh.joints[18] - Eigen::Vector3d(0.5, 0, 0)).norm(), 0.0, 1e-9);    // elbow stays
  // Half shoulder (unmoved), half elbow (rotated (0, 0.1) to (-0.1, 0)): the blend of both.
  EXPECT_NEAR((at(mesh, kSplit) - Eigen::Vector3d(0.45, 0.05, 0)).norm(), 0.0, 1e-6);
  // Vertices on the pelvis do not move.
  EXPECT_NEAR((at(mesh, kShaped) - Eigen::Vector3d(0, -1, 0)).norm(), 0.0, 1e-6);
}

TEST(BodyModel, ParentRotationCarriesTheChain) {
  const BodyModel model = BodyModel::loadNpz(TinyModel().write("pf2_tiny_chain.npz"));
  BodyParameters p;
  p.pose[16] = Eigen::Vector3d(0, 0, -kPi / 2);  // left shoulder down: x -> -y
  p.pose[18] = Eigen::Vector3d(0, 0, kPi / 2);   // elbow back up: forearm along +x again
  const BodyMesh mesh = model.evaluate(p);
  EXPECT_NEAR((mesh.joints[18] - Eigen::Vector3d(0.2, -0.3, 0)).norm(), 0.0, 1e-6);
  EXPECT_NEAR((at(mesh, kForearm) - Eigen::Vector3d(0.4, -0.3, 0)).norm(), 0.0, 1e-6);
  EXPECT_NEAR((mesh.joints[20] - Eigen::Vector3d(0.5, -0.3, 0)).norm(), 0.0, 1e-6);
}

TEST(BodyModel, ShapeBlendMovesVerticesAndRegressedJoints) {
  const BodyModel model = BodyModel::loadNpz(TinyModel().write("pf2_tiny_shape.npz"));
  BodyParameters p;
  p.shape = Eigen::VectorXd::Zero(12);  // extra coefficients beyond the model's are ignored
  p.shape[0] = 2.0;
  p.shape[5] = 100.0;
  const BodyMesh mesh = model.evaluate(p);
  EXPECT_NEAR((at(mesh, kShaped) - Eigen::Vector3d(0, -1, 0.2)).norm(), 0.0, 1e-6);
  EXPECT_NEAR((mesh.joints[18] - Eigen::Vector3d(0.7, 0, 0)).norm(), 0.0, 1e-6);
  EXPECT_NEAR(model.restJoints(p.shape)[18].x(), 0.7, 1e-6);
  // The forearm vertex follows its (moved) elbow only through posing: at rest it stays put.
  EXPECT_NEAR((at(mesh, kForearm) - Eigen::Vector3d(0.7, 0, 0)).norm(), 0.0, 1e-6);
  p.pose[18] = Eigen::Vector3d(0, 0, kPi / 2);
  const BodyMesh bent = model.evaluate(p);
  EXPECT_NEAR((at(bent, kForearm) - Eigen::Vector3d(0.7, 0.0, 0)).norm(), 0.0, 1e-6);  // on the joint now
  // Fewer coefficients than the model has: the rest count as zero.
  BodyParameters q;
  q.shape = Eigen::VectorXd::Constant(1, -1.0);
  EXPECT_NEAR(model.evaluate(q).vertices[kShaped].z(), -0.1f, 1e-6f);
}

TEST(BodyModel, PoseBlendShapesFollowSmplsFeature) {
  TinyModel tiny;
  // Feature index of joint 18's (R - I)(0, 1) entry: (18 - 1) * 9 + 0 * 3 + 1.
  const int feature = 17 * 9 + 1;
  tiny.posedirs[(3 * kShaped + 1) * 207 + feature] = 0.5f;  // moves kShaped's y
  const BodyModel model = BodyModel::loadNpz(tiny.write("pf2_tiny_posedirs.npz"));
  EXPECT_TRUE(model.hasPoseBlendShapes());
  BodyParameters p;
  p.pose[18] = Eigen::Vector3d(0, 0, kPi / 2);  // R(0, 1) = -sin(90) = -1
  EXPECT_NEAR(model.evaluate(p).vertices[kShaped].y(), -1.0f - 0.5f, 1e-6f);
}

TEST(BodyModel, Float64AndFortranOrderLoadTheSame) {
  const TinyModel tiny;
  auto arrays = tiny.arrays();
  // v_template as float64 in Fortran order (column by column).
  NpyArray f8;
  f8.descr = "<f8";
  f8.fortran_order = true;
  f8.shape = {kVertices, 3};
  std::vector<double> column_major;
  for (int c = 0; c < 3; ++c)
    for (int v = 0; v < kVertices; ++v) column_major.push_back(tiny.v_template[3 * v + c]);
  f8.bytes.resize(column_major.size() * sizeof(double));
  std::memcpy(f8.bytes.data(), column_major.data(), f8.bytes.size());
  replace(&arrays, "v_template", f8);
  const std::string path = testing::TempDir() + "pf2_tiny_f8.npz";
  writeNpz(path, arrays);
  BodyParameters p;
  p.pose[18] = Eigen::Vector3d(0.1, 0.2, 0.3);
  const BodyMesh a = BodyModel::loadNpz(path).evaluate(p);
  const BodyMesh b = BodyModel::loadNpz(tiny.write("pf2_tiny_f4.npz")).evaluate(p);
  for (int v = 0; v < kVertices; ++v) EXPECT_NEAR((at(a, v) - at(b, v)).norm(), 0.0, 1e-7);
}

TEST(BodyModel, BrokenModelsThrowNamingFileAndArray) {
  const TinyModel tiny;
  const std::size_t V = kVertices;
  {
    auto arrays = tiny.arrays();
    arrays.erase(arrays.begin() + 4);  // weights
    expectLoadError(arrays, "missing", {"'weights'", "missing"});
  }
  {
    auto arrays = tiny.arrays();
    replace(&arrays, "shapedirs", NpyArray::fromFloats({V, 2}, std::vector<float>(2 * V)));
    expectLoadError(arrays, "shape", {"'shapedirs'", "shape (27, 2)"});
  }
  {
    auto arrays = tiny.arrays();
    replace(&arrays, "v_template", NpyArray::fromInt32({V, 3}, std::vector<std::int32_t>(3 * V)));
    expectLoadError(arrays, "dtype", {"'v_template'", "dtype"});
  }
  {
    auto arrays = tiny.arrays();
    std::vector<std::int32_t> kintree = tiny.kintree;
    kintree[18] = 13;  // left elbow hung on the collar
    replace(&arrays, "kintree_table", NpyArray::fromInt32({2, kBodyJointCount}, kintree));
    expectLoadError(arrays, "tree", {"'kintree_table'", "joint 18"});
  }
  {
    auto arrays = tiny.arrays();
    replace(&arrays, "f", NpyArray::fromInt32({1, 3}, {0, 1, kVertices}));
    expectLoadError(arrays, "faces", {"'f'", "vertex 27"});
  }
  {
    auto arrays = tiny.arrays();
    std::vector<float> weights = tiny.weights;
    weights[3 * kBodyJointCount] = 0.5f;
    replace(&arrays, "weights", NpyArray::fromFloats({V, kBodyJointCount}, weights));
    expectLoadError(arrays, "weightsum", {"'weights'", "row 3"});
  }
  {
    auto arrays = tiny.arrays();
    std::vector<float> v = tiny.v_template;
    v[5] = std::nanf("");
    replace(&arrays, "v_template", NpyArray::fromFloats({V, 3}, v));
    expectLoadError(arrays, "nan", {"'v_template'", "NaN"});
  }
  {
    auto arrays = tiny.arrays();
    replace(&arrays, "posedirs", NpyArray::fromFloats({V, 3, 5}, std::vector<float>(V * 15)));
    expectLoadError(arrays, "posedirs", {"'posedirs'", "207"});
  }
}

TEST(BodyModel, TruncatedOrGarbledFilesThrowNamingTheFile) {
  const std::string whole = TinyModel().write("pf2_tiny_whole.npz");
  std::ifstream in(whole, std::ios::binary);
  std::stringstream content;
  content << in.rdbuf();
  const std::string bytes = content.str();
  const std::string path = testing::TempDir() + "pf2_tiny_cut.npz";
  for (std::size_t length = 0; length < bytes.size(); length += bytes.size() / 23 + 1) {
    {
      std::ofstream out(path, std::ios::binary | std::ios::trunc);
      out << bytes.substr(0, length);
    }
    try {
      BodyModel::loadNpz(path);
      ADD_FAILURE() << "no error at length " << length;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
  // An array whose .npy header is garbage: the error names the file and the array.
  auto arrays = TinyModel().arrays();
  NpyArray garbage = NpyArray::fromFloats({kVertices, 3}, TinyModel().v_template);
  garbage.descr = "%$#";
  replace(&arrays, "v_template", garbage);
  expectLoadError(arrays, "header", {"'v_template'", "dtype"});
}

TEST(BodyModel, DefaultPathFollowsTheEnvironment) {
  ::setenv("PF2_BODY_MODEL", "/nonexistent/pf2_model.npz", 1);
  EXPECT_EQ(BodyModel::defaultModelPath(), "/nonexistent/pf2_model.npz");
  try {
    BodyModel::loadDefault();
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/pf2_model.npz"), std::string::npos);
  }
  ::unsetenv("PF2_BODY_MODEL");
  EXPECT_NE(BodyModel::defaultModelPath().find("pf2_default_body.npz"), std::string::npos);
}

TEST(BodyModel, PolygonMeshAndFileExport) {
  const BodyModel model = BodyModel::loadNpz(TinyModel().write("pf2_tiny_export.npz"));
  const BodyMesh mesh = model.evaluate(BodyParameters());
  pcl::PolygonMesh polygon_mesh;
  toPolygonMesh(mesh, &polygon_mesh);
  EXPECT_EQ(polygon_mesh.cloud.width * polygon_mesh.cloud.height, static_cast<std::uint32_t>(kVertices));
  ASSERT_EQ(polygon_mesh.polygons.size(), 2u);
  const auto& polygon = polygon_mesh.polygons[0].vertices;
  ASSERT_EQ(polygon.size(), 3u);
  EXPECT_EQ(static_cast<int>(polygon[0]), kForearm);
  EXPECT_EQ(static_cast<int>(polygon[1]), kSplit);
  EXPECT_EQ(static_cast<int>(polygon[2]), kShaped);

  const std::string obj = testing::TempDir() + "pf2_tiny.obj";
  writeBodyMesh(obj, mesh);
  std::ifstream in(obj);
  std::string line;
  int vertices = 0, faces = 0;
  std::string first_face;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) == 0) ++vertices;
    if (line.rfind("f ", 0) == 0 && faces++ == 0) first_face = line;
  }
  EXPECT_EQ(vertices, kVertices);
  EXPECT_EQ(faces, 2);
  EXPECT_EQ(first_face, "f 25 26 27");  // 1-based

  const std::string ply = testing::TempDir() + "pf2_tiny.ply";
  writeBodyMesh(ply, mesh);
  std::ifstream ply_in(ply, std::ios::binary);
  std::stringstream content;
  content << ply_in.rdbuf();
  const std::string bytes = content.str();
  const std::size_t body = bytes.find("end_header\n");
  ASSERT_NE(body, std::string::npos);
  EXPECT_EQ(bytes.size() - body - 11, kVertices * 12u + 2 * 13u);
  EXPECT_THROW(writeBodyMesh(testing::TempDir() + "pf2_tiny.stl", mesh), Error);
}

TEST(BodyModel, PoseFile) {
  const std::string path = testing::TempDir() + "pf2_pose.txt";
  {
    std::ofstream out(path);
    out << "# walking\nleft_knee 0.5 0 0\n\n  right_elbow 0 0.25 -1  # comment\n";
  }
  BodyParameters p;
  readBodyPoseFile(path, &p);
  EXPECT_EQ(p.pose[4], Eigen::Vector3d(0.5, 0, 0));
  EXPECT_EQ(p.pose[19], Eigen::Vector3d(0, 0.25, -1));
  EXPECT_EQ(p.pose[0], Eigen::Vector3d::Zero());
  for (const std::string bad : {"left_tail 1 2 3\n", "left_knee 1 2\n", "left_knee 1 2 3 4\n", "left_knee 1 nan 3\n"}) {
    {
      std::ofstream out(path);
      out << "# header\n" << bad;
    }
    try {
      readBodyPoseFile(path, &p);
      FAIL() << "no error for " << bad;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(path + ":2:"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace pf2
