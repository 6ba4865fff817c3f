#pragma once
// SMPL-compatible linear-blend-skinning body model: 24 joints in SMPL's kinematic tree and order,
// pose as 24 axis-angle rotations (relative to the parent joint), shape coefficients (betas),
// root translation. Units: metres. Body frame as SMPL's: y up, the body faces +z, x to its left;
// all-zero pose = SMPL's T pose. See docs/body.md.
//
//   vertices = LBS(template + shapedirs * betas + posedirs * pose_feature, joints, weights)
//   joints   = J_regressor * (template + shapedirs * betas)
//
// The data come from an SMPL-format .npz (v_template, shapedirs, posedirs, J_regressor, weights,
// kintree_table, f): the project's own default model (built from CC0 MakeHuman/MPFB2 data) or the
// official SMPL model for users who hold its licence.
#include <array>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace pcl {
struct PolygonMesh;
}

namespace pf2 {

constexpr int kBodyJointCount = 24;

// SMPL's joint order: 0 pelvis, 1 left_hip, 2 right_hip, 3 spine1, 4 left_knee, 5 right_knee,
// 6 spine2, 7 left_ankle, 8 right_ankle, 9 spine3, 10 left_foot, 11 right_foot, 12 neck,
// 13 left_collar, 14 right_collar, 15 head, 16 left_shoulder, 17 right_shoulder, 18 left_elbow,
// 19 right_elbow, 20 left_wrist, 21 right_wrist, 22 left_hand, 23 right_hand.
extern const std::array<const char*, kBodyJointCount> kBodyJointNames;
// Parent of each joint in that order; -1 for the pelvis (root).
extern const std::array<int, kBodyJointCount> kBodyJointParents;

struct BodyParameters {
  // Axis-angle rotation of each joint relative to its parent (radians); all zero = rest pose.
  std::array<Eigen::Vector3d, kBodyJointCount> pose;
  // Shape coefficients; missing ones count as zero, extra ones beyond the model's are ignored.
  Eigen::VectorXd shape;
  // Translation of the root (added after posing), metres.
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();

  BodyParameters() : shape(Eigen::VectorXd::Zero(10)) {
    for (auto& p : pose) p.setZero();
  }
};

struct BodyMesh {
  std::vector<Eigen::Vector3f> vertices;             // posed, metres
  std::vector<Eigen::Vector3i> triangles;            // vertex indices, counter-clockwise outward
  std::array<Eigen::Vector3d, kBodyJointCount> joints;  // posed joint positions, metres
};

// Size of a rest-pose body: stature (top of head to soles), the lowest point's y (the soles;
// the floor under the body in the body frame) and the enclosed volume.
struct BodyMeasures {
  double stature = 0.0;  // m
  double min_y = 0.0;    // m
  double volume = 0.0;   // m^3 (signed; positive because the triangles face outward)
};

// Immutable after loading: every const method is thread safe, so one model can be shared by all
// threads (e.g. through std::shared_ptr<const BodyModel>).
class BodyModel {
 public:
  // Reads an SMPL-format .npz. Throws pf2::Error naming the file and the array on any problem
  // (missing array, wrong shape or dtype, corrupt zip, a kinematic tree other than SMPL's).
  // Float arrays may be float32 or float64, C or Fortran order; all-zero posedirs count as none.
  static BodyModel loadNpz(const std::string& path);
  // The model that ships with the project (see defaultModelPath). Throws pf2::Error when missing.
  static BodyModel loadDefault();
  // $PF2_BODY_MODEL when set, else the shipped modules/body/data/pf2_default_body.npz (the path
  // is compiled in from the source tree).
  static std::string defaultModelPath();

  int vertexCount() const { return static_cast<int>(v_template_.size() / 3); }
  int shapeCount() const { return static_cast<int>(shapedirs_.cols()); }
  bool hasPoseBlendShapes() const { return posedirs_.size() > 0; }
  const std::vector<Eigen::Vector3i>& triangles() const { return triangles_; }

  // Poses the model. Thread safe (const).
  BodyMesh evaluate(const BodyParameters& parameters) const;
  // The posed joints alone, as evaluate() gives them, without skinning the mesh. Thread safe.
  std::array<Eigen::Vector3d, kBodyJointCount> posedJoints(const BodyParameters& parameters) const;
  // Rest-pose joints for a shape (no pose, no translation). Thread safe.
  std::array<Eigen::Vector3d, kBodyJointCount> restJoints(const Eigen::VectorXd& shape) const;
  // Rest-pose vertices for a shape (template + shape blend shapes), 3V values x0 y0 z0 x1 ...
  Eigen::VectorXf restVertices(const Eigen::VectorXd& shape) const;
  // Stature, soles and volume of the rest mesh for a shape. Thread safe.
  BodyMeasures restMeasures(const Eigen::VectorXd& shape) const;
  // Per-vertex skinning weights (vertexCount x 24), rows sum to 1.
  const Eigen::MatrixXf& weights() const { return weights_; }

 private:
  Eigen::VectorXf v_template_;       // 3V: x, y, z of each vertex
  Eigen::MatrixXf shapedirs_;        // 3V x B
  Eigen::MatrixXf posedirs_;         // 3V x 207, empty when the model has no pose blend shapes
  // The joint regressor applied ahead of time (joints are linear in the shape): 72 = 24 x (x, y, z).
  Eigen::VectorXd joint_template_;   // J_regressor * v_template
  Eigen::MatrixXd joint_shapedirs_;  // 72 x B: J_regressor * shapedirs
  Eigen::MatrixXf weights_;          // V x 24
  // The non-zero weights of each vertex (compressed rows of weights_): skinning touches only these.
  std::vector<int> weight_begin_;    // V + 1 offsets
  std::vector<int> weight_joint_;
  std::vector<float> weight_value_;
  std::vector<Eigen::Vector3i> triangles_;
};

// The posed mesh as a PCL polygon mesh (vertices in a pcl::PointCloud<pcl::PointXYZ> blob).
void toPolygonMesh(const BodyMesh& mesh, pcl::PolygonMesh* polygon_mesh);

}  // namespace pf2
