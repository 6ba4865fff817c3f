// The shipped default model (modules/body/data/pf2_default_body.npz): anatomy checks that need
// no other data, and, when ../shared/data/body_mpfb2 is present, a check that the converter
// reproduces the shipped file.
#include <sys/stat.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "pf2/body/body_model.h"
#include "pf2/body/mpfb2_converter.h"
#include "pf2/body/npy.h"
#include "pf2/core/error.h"

namespace pf2 {
namespace {

const std::string kShippedModel = std::string(PF2_SOURCE_DIR) + "/modules/body/data/pf2_default_body.npz";

const BodyModel& defaultModel() {
  static const BodyModel model = [] {
    ::unsetenv("PF2_BODY_MODEL");
    return BodyModel::loadDefault();
  }();
  return model;
}

int joint(const char* name) {
  for (int j = 0; j < kBodyJointCount; ++j) {
    if (std::strcmp(kBodyJointNames[j], name) == 0) return j;
  }
  ADD_FAILURE() << "no joint " << name;
  return 0;
}



Eigen::VectorXd unitShape(const BodyModel& model, int k, double value) {
  Eigen::VectorXd shape = Eigen::VectorXd::Zero(model.shapeCount());
  shape[k] = value;
  return shape;
}

TEST(DefaultBody, LoadsWithSmplStructure) {
  const BodyModel& model = defaultModel();
  EXPECT_EQ(model.vertexCount(), 13380);
  EXPECT_EQ(model.triangles().size(), 26756u);
  EXPECT_GE(model.shapeCount(), 10);
  EXPECT_FALSE(model.hasPoseBlendShapes());
  for (int v = 0; v < model.vertexCount(); ++v) ASSERT_NEAR(model.weights().row(v).sum(), 1.0f, 1e-5f) << v;
  // Outward normals: the enclosed signed volume is positive and human-sized (litres / 1000).
  const BodyMeasures m = model.restMeasures(Eigen::VectorXd::Zero(model.shapeCount()));
  EXPECT_GT(m.volume, 0.03);
  EXPECT_LT(m.volume, 0.12);
}

TEST(DefaultBody, JointsAreWhereABodyHasThem) {
  const BodyModel& model = defaultModel();
  const auto J = model.restJoints(Eigen::VectorXd::Zero(model.shapeCount()));
  // Origin at the pelvis joint; the spine, neck and head stack up above it.
  EXPECT_LT(J[joint("pelvis")].norm(), 0.01);
  EXPECT_GT(J[joint("spine1")].y(), J[joint("pelvis")].y());
  EXPECT_GT(J[joint("spine2")].y(), J[joint("spine1")].y());
  EXPECT_GT(J[joint("spine3")].y(), J[joint("spine2")].y());
  EXPECT_GT(J[joint("neck")].y(), J[joint("spine3")].y());
  EXPECT_GT(J[joint("head")].y(), J[joint("neck")].y());
  EXPECT_GT(J[joint("left_hip")].y(), J[joint("left_knee")].y());
  EXPECT_GT(J[joint("left_knee")].y(), J[joint("left_ankle")].y());
  // Left at +x, right mirrored at -x.
  for (int j = 0; j < kBodyJointCount; ++j) {
    const std::string name = kBodyJointNames[j];
    if (name.rfind("left_", 0) != 0) continue;
    const int r = joint(("right_" + name.substr(5)).c_str());
    EXPECT_GT(J[j].x(), 0.01) << name;
    EXPECT_NEAR(J[j].x(), -J[r].x(), 1e-3) << name;
    EXPECT_NEAR(J[j].y(), J[r].y(), 1e-3) << name;
  }
  // SMPL's T pose: arms straight out along x at shoulder height, legs straight down.
  for (const char* arm : {"left_elbow", "left_wrist", "left_hand"}) {
    EXPECT_NEAR(J[joint(arm)].y(), J[joint("left_shoulder")].y(), 0.02) << arm;
  }
  EXPECT_GT(J[joint("left_wrist")].x(), J[joint("left_elbow")].x() + 0.15);
  EXPECT_NEAR(J[joint("left_ankle")].x(), J[joint("left_hip")].x(), 0.02);
  // Ankles a few centimetres above the soles; the soles near y = -0.86 like SMPL's.
  const BodyMeasures m = model.restMeasures(Eigen::VectorXd::Zero(model.shapeCount()));
  EXPECT_GT(J[joint("left_ankle")].y() - m.min_y, 0.03);
  EXPECT_LT(J[joint("left_ankle")].y() - m.min_y, 0.12);
  EXPECT_GT(m.min_y, -1.0);
  EXPECT_LT(m.min_y, -0.75);
}

TEST(DefaultBody, RestStatureIsAdult) {
  const BodyModel& model = defaultModel();
  const BodyMeasures m = model.restMeasures(Eigen::VectorXd::Zero(model.shapeCount()));
  EXPECT_GT(m.stature, 1.5);
  EXPECT_LT(m.stature, 1.9);
}

TEST(DefaultBody, ShapeZeroMakesTallerAndAnotherMakesHeavier) {
  const BodyModel& model = defaultModel();
  // Coefficient 0: stature grows monotonically (documented: about +9 cm per unit).
  double previous = 0.0;
  for (double b = -2.0; b <= 2.0; b += 1.0) {
    const BodyMeasures m = model.restMeasures(unitShape(model, 0, b));
    if (b > -2.0) {
      EXPECT_GT(m.stature, previous + 0.05) << b;
    }
    previous = m.stature;
  }
  // The soles stay put (the pelvis rises instead), so people stand on the same floor.
  EXPECT_NEAR(model.restMeasures(unitShape(model, 0, 2.0)).min_y, model.restMeasures(unitShape(model, 0, -2.0)).min_y, 0.01);
  // Coefficient 3: more volume at almost the same stature (documented: weight).
  const double base_stature = model.restMeasures(unitShape(model, 3, 0.0)).stature;
  previous = 0.0;
  for (double b = -2.0; b <= 2.0; b += 1.0) {
    const BodyMeasures m = model.restMeasures(unitShape(model, 3, b));
    if (b > -2.0) {
      EXPECT_GT(m.volume, previous * 1.05) << b;
    }
    EXPECT_NEAR(m.stature, base_stature, 0.01) << b;
    previous = m.volume;
  }
}

TEST(DefaultBody, LeftKneeMovesTheLeftAnkleOnly) {
  const BodyModel& model = defaultModel();
  const BodyMesh rest = model.evaluate(BodyParameters());
  BodyParameters p;
  p.pose[joint("left_knee")] = Eigen::Vector3d(1.0, 0, 0);  // bend 1 rad
  const BodyMesh bent = model.evaluate(p);
  const int left_ankle = joint("left_ankle"), right_ankle = joint("right_ankle");
  // The ankle turns about the knee's x axis: a chord of 2 r sin(0.5) with r its distance to the axis.
  Eigen::Vector3d shin = rest.joints[left_ankle] - rest.joints[joint("left_knee")];
  shin.x() = 0.0;
  EXPECT_NEAR((bent.joints[left_ankle] - rest.joints[left_ankle]).norm(), 2.0 * shin.norm() * std::sin(0.5), 1e-9);
  EXPECT_LT(bent.joints[left_ankle].z(), rest.joints[left_ankle].z() - 0.1);   // +x rotation: foot goes back
  EXPECT_EQ(bent.joints[right_ankle], rest.joints[right_ankle]);
  // Vertices skinned only to the right leg do not move; the left sole does.
  int moved_left = 0, moved_right = 0, left_count = 0, right_count = 0;
  for (int v = 0; v < model.vertexCount(); ++v) {
    const float left = model.weights()(v, left_ankle) + model.weights()(v, joint("left_foot"));
    const float right = model.weights()(v, right_ankle) + model.weights()(v, joint("right_foot"));
    const float distance = (bent.vertices[v] - rest.vertices[v]).norm();
    if (left > 0.99f) {
      ++left_count;
      moved_left += distance > 0.1f;
    }
    if (right > 0.99f) {
      ++right_count;
      moved_right += distance > 0.0f;
    }
  }
  EXPECT_GT(left_count, 100);
  EXPECT_EQ(moved_left, left_count);
  EXPECT_GT(right_count, 100);
  EXPECT_EQ(moved_right, 0);
}

bool exists(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0;
}

TEST(DefaultBody, ConverterReproducesTheShippedFile) {
  const std::string source = std::string(PF2_SHARED_DATA) + "/body_mpfb2";
  if (!exists(source + "/3dobjs/base.obj")) GTEST_SKIP() << "no MPFB2 data at " << source;
  Mpfb2Converter::Report report;
  const auto arrays = Mpfb2Converter().convert(source, &report);
  EXPECT_LT(report.max_joint_error, 0.03);
  double explained = 0.0;
  for (const double e : report.explained_variance) explained += e;
  EXPECT_GT(explained, 0.99);

  const NpzReader shipped(kShippedModel);
  ASSERT_EQ(shipped.names().size(), arrays.size());
  for (const auto& [name, array] : arrays) {
    const NpyArray stored = shipped.read(name);
    EXPECT_EQ(stored.descr, array.descr) << name;
    ASSERT_EQ(stored.shape, array.shape) << name;
    const std::vector<double> a = array.toDoubles(name), b = stored.toDoubles(name);
    double worst = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(a[i] - b[i]));
    // Floating-point sums may differ in the last bits between compilers; structure must not.
    EXPECT_LT(worst, array.isFloat() ? 1e-5 : 0.5) << name;
  }
}

TEST(DefaultBody, ConverterNamesTheMissingFile) {
  try {
    Mpfb2Converter().convert(testing::TempDir() + "pf2_no_mpfb2_here");
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("base.obj"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pf2
