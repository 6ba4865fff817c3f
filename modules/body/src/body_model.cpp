#include "pf2/body/body_model.h"

#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cmath>
#include <algorithm>
#include <cstdlib>
#include <limits>
#include <type_traits>
#include <sys/stat.h>

#include <Eigen/Geometry>

#include "pf2/body/npy.h"
#include "pf2/core/error.h"

namespace pf2 {

const std::array<const char*, kBodyJointCount> kBodyJointNames = {
    "pelvis",     "left_hip",       "right_hip",      "spine1",      "left_knee",   "right_knee",
    "spine2",     "left_ankle",     "right_ankle",    "spine3",      "left_foot",   "right_foot",
    "neck",       "left_collar",    "right_collar",   "head",        "left_shoulder", "right_shoulder",
    "left_elbow", "right_elbow",    "left_wrist",     "right_wrist", "left_hand",   "right_hand"};

const std::array<int, kBodyJointCount> kBodyJointParents = {
    -1, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9, 12, 13, 14, 16, 17, 18, 19, 20, 21};

namespace {

constexpr int kPoseFeatureCount = (kBodyJointCount - 1) * 9;

std::string shapeString(const std::vector<std::size_t>& shape) {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) s += (i ? ", " : "") + std::to_string(shape[i]);
  return s + ")";
}

// Reads a numeric array and checks its shape against `expected` (0 = any size).
std::vector<double> readArray(const NpzReader& npz, const std::string& name,
                              const std::vector<std::size_t>& expected, bool want_integer,
                              std::vector<std::size_t>* shape_out = nullptr) {
  const std::string where = npz.path() + ": array '" + name + "'";
  const NpyArray array = npz.read(name);
  if (want_integer ? !array.isInteger() : !(array.isFloat())) {
    throw Error(where + ": dtype '" + array.descr + "', expected " +
                (want_integer ? "an integer type" : "float32 or float64"));
  }
  bool shape_ok = array.shape.size() == expected.size();
  for (std::size_t i = 0; shape_ok && i < expected.size(); ++i) {
    shape_ok = expected[i] == 0 || expected[i] == array.shape[i];
  }
  if (!shape_ok) {
    std::string wanted = "(";
    for (std::size_t i = 0; i < expected.size(); ++i) {
      wanted += (i ? ", " : "") + (expected[i] ? std::to_string(expected[i]) : std::string("*"));
    }
    throw Error(where + ": shape " + shapeString(array.shape) + ", expected " + wanted + ")");
  }
  std::vector<double> values = array.toDoubles(where);
  for (const double v : values) {
    if (!std::isfinite(v)) throw Error(where + ": contains NaN or infinity");
  }
  if (shape_out) *shape_out = array.shape;
  return values;
}

bool fileExists(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

}  // namespace

BodyModel BodyModel::loadNpz(const std::string& path) {
  const NpzReader npz(path);
  BodyModel model;

  std::vector<std::size_t> shape;
  const std::vector<double> v_template = readArray(npz, "v_template", {0, 3}, false, &shape);
  const std::size_t V = shape[0];
  if (V == 0) throw Error(path + ": array 'v_template': no vertices");
  model.v_template_ = Eigen::Map<const Eigen::VectorXd>(v_template.data(), 3 * V).cast<float>();

  const std::vector<double> shapedirs = readArray(npz, "shapedirs", {V, 3, 0}, false, &shape);
  const std::size_t B = shape[2];
  // (V, 3, B) in C order is a row-major (3V x B) matrix.
  model.shapedirs_ = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
                         shapedirs.data(), 3 * V, B).cast<float>();

  {
    const std::vector<double> posedirs = readArray(npz, "posedirs", {V, 3, 0}, false, &shape);
    if (shape[2] != 0 && shape[2] != static_cast<std::size_t>(kPoseFeatureCount)) {
      throw Error(path + ": array 'posedirs': shape " + shapeString(shape) + ", expected (" +
                  std::to_string(V) + ", 3, " + std::to_string(kPoseFeatureCount) + ") or no pose blend shapes (0)");
    }
    bool any = false;
    for (const double v : posedirs) any = any || v != 0.0;
    if (any) {
      model.posedirs_ = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
                            posedirs.data(), 3 * V, kPoseFeatureCount).cast<float>();
    }
  }

  const std::vector<double> regressor = readArray(npz, "J_regressor", {kBodyJointCount, V}, false);
  {
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> J(
        regressor.data(), kBodyJointCount, V);
    const Eigen::MatrixXd template_xyz =
        model.v_template_.cast<double>().reshaped(3, V).transpose();  // V x 3
    const Eigen::MatrixXd joints = J * template_xyz;                   // 24 x 3
    model.joint_template_ = joints.transpose().reshaped();
    model.joint_shapedirs_.resize(3 * kBodyJointCount, B);
    for (std::size_t b = 0; b < B; ++b) {
      const Eigen::MatrixXd dir = model.shapedirs_.col(b).cast<double>().reshaped(3, V).transpose();
      model.joint_shapedirs_.col(b) = (J * dir).transpose().reshaped();
    }
  }

  const std::vector<double> weights = readArray(npz, "weights", {V, kBodyJointCount}, false);
  model.weights_.resize(V, kBodyJointCount);
  model.weight_begin_.assign(1, 0);
  for (std::size_t v = 0; v < V; ++v) {
    double sum = 0.0;
    for (int j = 0; j < kBodyJointCount; ++j) {
      const double w = weights[v * kBodyJointCount + j];
      if (w < -1e-6) {
        throw Error(path + ": array 'weights': negative weight at vertex " + std::to_string(v));
      }
      sum += w;
    }
    if (std::abs(sum - 1.0) > 1e-3) {
      throw Error(path + ": array 'weights': row " + std::to_string(v) + " sums to " + std::to_string(sum) +
                  ", expected 1");
    }
    for (int j = 0; j < kBodyJointCount; ++j) {
      const float w = static_cast<float>(std::max(0.0, weights[v * kBodyJointCount + j]) / sum);
      model.weights_(static_cast<Eigen::Index>(v), j) = w;
      if (w > 0.0f) {
        model.weight_joint_.push_back(j);
        model.weight_value_.push_back(w);
      }
    }
    model.weight_begin_.push_back(static_cast<int>(model.weight_joint_.size()));
  }

  const std::vector<double> kintree = readArray(npz, "kintree_table", {2, kBodyJointCount}, true);
  for (int j = 0; j < kBodyJointCount; ++j) {
    const bool id_ok = kintree[kBodyJointCount + j] == j;
    const bool parent_ok = j == 0 || kintree[j] == kBodyJointParents[j];
    if (!id_ok || !parent_ok) {
      throw Error(path + ": array 'kintree_table': joint " + std::to_string(j) +
                  " does not follow SMPL's kinematic tree");
    }
  }

  const std::vector<double> faces = readArray(npz, "f", {0, 3}, true, &shape);
  model.triangles_.resize(shape[0]);
  for (std::size_t i = 0; i < shape[0]; ++i) {
    for (int k = 0; k < 3; ++k) {
      const double index = faces[i * 3 + k];
      if (index < 0 || index >= static_cast<double>(V)) {
        throw Error(path + ": array 'f': face " + std::to_string(i) + " refers to vertex " +
                    std::to_string(static_cast<long long>(index)) + " of " + std::to_string(V));
      }
      model.triangles_[i][k] = static_cast<int>(index);
    }
  }
  return model;
}

std::string BodyModel::defaultModelPath() {
  if (const char* env = std::getenv("PF2_BODY_MODEL"); env != nullptr && *env != '\0') return env;
  return PF2_BODY_DEFAULT_MODEL;
}

BodyModel BodyModel::loadDefault() {
  const std::string path = defaultModelPath();
  if (!fileExists(path)) {
    throw fileError(path, "default body model not found (set PF2_BODY_MODEL to an SMPL-format .npz)");
  }
  return loadNpz(path);
}

Eigen::VectorXf BodyModel::restVertices(const Eigen::VectorXd& shape) const {
  const Eigen::Index used = std::min<Eigen::Index>(shape.size(), shapedirs_.cols());
  Eigen::VectorXf v = v_template_;
  if (used > 0) v.noalias() += shapedirs_.leftCols(used) * shape.head(used).cast<float>();
  return v;
}

std::array<Eigen::Vector3d, kBodyJointCount> BodyModel::restJoints(const Eigen::VectorXd& shape) const {
  const Eigen::Index used = std::min<Eigen::Index>(shape.size(), joint_shapedirs_.cols());
  Eigen::VectorXd J = joint_template_;
  if (used > 0) J.noalias() += joint_shapedirs_.leftCols(used) * shape.head(used);
  std::array<Eigen::Vector3d, kBodyJointCount> joints;
  for (int j = 0; j < kBodyJointCount; ++j) joints[j] = J.segment<3>(3 * j);
  return joints;
}

BodyMeasures BodyModel::restMeasures(const Eigen::VectorXd& shape) const {
  const Eigen::VectorXf v = restVertices(shape);
  BodyMeasures m;
  double top = -std::numeric_limits<double>::infinity();
  m.min_y = std::numeric_limits<double>::infinity();
  for (int i = 0; i < vertexCount(); ++i) {
    top = std::max(top, static_cast<double>(v[3 * i + 1]));
    m.min_y = std::min(m.min_y, static_cast<double>(v[3 * i + 1]));
  }
  for (const auto& t : triangles_) {
    const Eigen::Vector3d a = v.segment<3>(3 * t[0]).cast<double>();
    const Eigen::Vector3d b = v.segment<3>(3 * t[1]).cast<double>();
    const Eigen::Vector3d c = v.segment<3>(3 * t[2]).cast<double>();
    m.volume += a.dot(b.cross(c)) / 6.0;
  }
  m.stature = top - m.min_y;
  return m;
}

namespace {

std::array<Eigen::Matrix3d, kBodyJointCount> jointRotations(const BodyParameters& parameters) {
  std::array<Eigen::Matrix3d, kBodyJointCount> R;
  for (int j = 0; j < kBodyJointCount; ++j) {
    const Eigen::Vector3d& r = parameters.pose[j];
    const double angle = r.norm();
    R[j] = angle > 1e-12 ? Eigen::AngleAxisd(angle, r / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
  }
  return R;
}

// The posed transform G_j of each joint (rotation and position, root translation not added), down
// the kinematic tree from the rest joints J.
std::array<Eigen::Isometry3d, kBodyJointCount> jointTransforms(const std::array<Eigen::Matrix3d, kBodyJointCount>& R,
                                                               const std::array<Eigen::Vector3d, kBodyJointCount>& J) {
  std::array<Eigen::Isometry3d, kBodyJointCount> G;
  for (int j = 0; j < kBodyJointCount; ++j) {
    Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
    local.linear() = R[j];
    const int parent = kBodyJointParents[j];
    local.translation() = parent < 0 ? J[j] : Eigen::Vector3d(J[j] - J[parent]);
    G[j] = parent < 0 ? local : G[parent] * local;
  }
  return G;
}

}  // namespace

std::array<Eigen::Vector3d, kBodyJointCount> BodyModel::posedJoints(const BodyParameters& parameters) const {
  const auto G = jointTransforms(jointRotations(parameters), restJoints(parameters.shape));
  std::array<Eigen::Vector3d, kBodyJointCount> joints;
  for (int j = 0; j < kBodyJointCount; ++j) joints[j] = G[j].translation() + parameters.translation;
  return joints;
}

BodyMesh BodyModel::evaluate(const BodyParameters& parameters) const {
  const int V = vertexCount();
  Eigen::VectorXf v_posed = restVertices(parameters.shape);
  const std::array<Eigen::Vector3d, kBodyJointCount> J = restJoints(parameters.shape);
  const std::array<Eigen::Matrix3d, kBodyJointCount> R = jointRotations(parameters);
  if (hasPoseBlendShapes()) {
    // SMPL's pose feature: (R_j - I) of joints 1..23, each 3x3 row-major.
    Eigen::VectorXf feature(kPoseFeatureCount);
    for (int j = 1; j < kBodyJointCount; ++j) {
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
          feature[(j - 1) * 9 + r * 3 + c] = static_cast<float>(R[j](r, c) - (r == c ? 1.0 : 0.0));
        }
      }
    }
    v_posed.noalias() += posedirs_ * feature;
  }

  // The skinning transform of each joint, A_j = G_j * [I | -J_j], plus the root translation.
  BodyMesh mesh;
  const std::array<Eigen::Isometry3d, kBodyJointCount> G = jointTransforms(R, J);
  std::array<Eigen::Matrix<float, 3, 4>, kBodyJointCount> A;
  for (int j = 0; j < kBodyJointCount; ++j) {
    mesh.joints[j] = G[j].translation() + parameters.translation;
    Eigen::Matrix<double, 3, 4> a;
    a.leftCols<3>() = G[j].linear();
    a.col(3) = G[j].translation() - G[j].linear() * J[j] + parameters.translation;
    A[j] = a.cast<float>();
  }

  mesh.vertices.resize(V);
  for (int v = 0; v < V; ++v) {
    Eigen::Matrix<float, 3, 4> T = Eigen::Matrix<float, 3, 4>::Zero();
    for (int k = weight_begin_[v]; k < weight_begin_[v + 1]; ++k) T += weight_value_[k] * A[weight_joint_[k]];
    mesh.vertices[v] = T.leftCols<3>() * v_posed.segment<3>(3 * v) + T.col(3);
  }
  mesh.triangles = triangles_;
  return mesh;
}

void toPolygonMesh(const BodyMesh& mesh, pcl::PolygonMesh* polygon_mesh) {
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.resize(mesh.vertices.size());
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    cloud[i].x = mesh.vertices[i].x();
    cloud[i].y = mesh.vertices[i].y();
    cloud[i].z = mesh.vertices[i].z();
  }
  pcl::toPCLPointCloud2(cloud, polygon_mesh->cloud);
  polygon_mesh->polygons.resize(mesh.triangles.size());
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    auto& indices = polygon_mesh->polygons[i].vertices;
    indices.resize(3);
    using Index = std::decay_t<decltype(indices)>::value_type;
    for (int k = 0; k < 3; ++k) indices[k] = static_cast<Index>(mesh.triangles[i][k]);
  }
}

}  // namespace pf2
