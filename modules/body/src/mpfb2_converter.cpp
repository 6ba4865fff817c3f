#include "pf2/body/mpfb2_converter.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <map>
#include <numeric>
#include <sstream>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "pf2/body/body_model.h"
#include "pf2/core/error.h"

namespace pf2 {
namespace {

using Json = nlohmann::json;

// The rig bone whose head is each SMPL joint (in SMPL order, left = _l).
constexpr std::array<const char*, kBodyJointCount> kJointBones = {
    "pelvis",     "thigh_l",    "thigh_r",    "spine_01",   "calf_l",     "calf_r",
    "spine_02",   "foot_l",     "foot_r",     "spine_03",   "ball_l",     "ball_r",
    "neck_01",    "clavicle_l", "clavicle_r", "head",       "upperarm_l", "upperarm_r",
    "lowerarm_l", "lowerarm_r", "hand_l",     "hand_r",     "middle_01_l", "middle_01_r"};

// The SMPL segment (joint) that a rig bone's skinning weight goes to.
int segmentOfBone(const std::string& bone) {
  for (int j = 0; j < kBodyJointCount; ++j) {
    if (bone == kJointBones[j] && j != 22 && j != 23) return j;
  }
  if (bone == "Root") return 0;
  // Fingers and thumb move with SMPL's hand joint.
  for (const char* finger : {"thumb_", "index_", "middle_", "ring_", "pinky_"}) {
    if (bone.rfind(finger, 0) == 0) return bone.back() == 'l' ? 22 : 23;
  }
  return -1;
}

struct Obj {
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::vector<int>> faces;
};

Obj readObj(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open");
  Obj obj;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.rfind("v ", 0) == 0) {
      std::istringstream s(line.substr(2));
      Eigen::Vector3d v;
      if (!(s >> v.x() >> v.y() >> v.z())) throw fileError(path, line_number, "bad vertex line");
      obj.vertices.push_back(v);
    } else if (line.rfind("f ", 0) == 0) {
      std::istringstream s(line.substr(2));
      std::vector<int> face;
      std::string token;
      while (s >> token) {
        const int index = std::atoi(token.c_str());
        if (index <= 0) throw fileError(path, line_number, "unsupported face index '" + token + "'");
        face.push_back(index - 1);
      }
      if (face.size() < 3) throw fileError(path, line_number, "face with fewer than 3 vertices");
      obj.faces.push_back(face);
    }
  }
  for (const auto& face : obj.faces) {
    for (const int i : face) {
      if (i >= static_cast<int>(obj.vertices.size())) throw fileError(path, "face index beyond the vertices");
    }
  }
  return obj;
}

Json readJson(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw fileError(path, "cannot open");
  try {
    return Json::parse(in);
  } catch (const std::exception& e) {
    throw fileError(path, std::string("bad JSON: ") + e.what());
  }
}

struct Target {
  std::vector<int> indices;
  std::vector<Eigen::Vector3d> offsets;
};

Target readTarget(const std::string& path, int vertex_count) {
  gzFile file = gzopen(path.c_str(), "rb");
  if (file == nullptr) throw fileError(path, "cannot open");
  Target target;
  char buffer[256];
  int line_number = 0;
  while (gzgets(file, buffer, sizeof(buffer)) != nullptr) {
    ++line_number;
    int index = 0;
    double dx = 0, dy = 0, dz = 0;
    if (buffer[0] == '#' || buffer[0] == '\n') continue;
    if (std::sscanf(buffer, "%d %lf %lf %lf", &index, &dx, &dy, &dz) != 4 || index < 0 || index >= vertex_count) {
      gzclose(file);
      throw fileError(path, line_number, "bad target line");
    }
    target.indices.push_back(index);
    target.offsets.emplace_back(dx, dy, dz);
  }
  int error = 0;
  gzerror(file, &error);
  gzclose(file);
  if (error != Z_OK && error != Z_STREAM_END) throw fileError(path, "corrupt gzip data");
  return target;
}

// The weights of a slider value over its interpolation points (MakeHuman's macro modifiers):
// value in [0,1], points at the given slider positions; linear between neighbours.
std::vector<double> sliderWeights(double value, const std::vector<double>& points) {
  std::vector<double> w(points.size(), 0.0);
  if (value <= points.front()) {
    w.front() = 1.0;
    return w;
  }
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    if (value <= points[i + 1]) {
      const double t = (value - points[i]) / (points[i + 1] - points[i]);
      w[i] = 1.0 - t;
      w[i + 1] = t;
      return w;
    }
  }
  w.back() = 1.0;
  return w;
}

// Uniform [0,1) from the top 53 bits: identical on every platform (unlike std distributions).
double uniform01(std::uint64_t* state) {
  // splitmix64
  std::uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * (1.0 / 9007199254740992.0);
}

struct Setting {
  double gender, age, muscle, weight, height, proportions;
  std::array<double, 3> race;
};

struct TargetTerm {
  std::string file;
  std::function<double(const Setting&)> weight;
};

const std::vector<std::string> kRaces = {"african", "asian", "caucasian"};
const std::vector<std::string> kGenders = {"female", "male"};
const std::vector<std::string> kAges = {"young", "old"};  // adults only: baby, child never weigh in
const std::vector<std::string> kMuscles = {"minmuscle", "averagemuscle", "maxmuscle"};
const std::vector<std::string> kWeights = {"minweight", "averageweight", "maxweight"};

double genderWeight(const Setting& s, int g) { return g == 0 ? 1.0 - s.gender : s.gender; }
// Age slider: 0.5 = young (25 years), 1.0 = old (90 years); below 0.5 the child targets would start.
double ageWeight(const Setting& s, int a) { return sliderWeights(s.age, {0.5, 1.0})[a]; }
double muscleWeight(const Setting& s, int m) { return sliderWeights(s.muscle, {0.0, 0.5, 1.0})[m]; }
double weightWeight(const Setting& s, int w) { return sliderWeights(s.weight, {0.0, 0.5, 1.0})[w]; }

std::vector<TargetTerm> macroTerms() {
  std::vector<TargetTerm> terms;
  for (int r = 0; r < 3; ++r) {
    for (int g = 0; g < 2; ++g) {
      for (int a = 0; a < 2; ++a) {
        terms.push_back({kRaces[r] + "-" + kGenders[g] + "-" + kAges[a] + ".target.gz",
                         [=](const Setting& s) { return s.race[r] * genderWeight(s, g) * ageWeight(s, a); }});
      }
    }
  }
  for (int g = 0; g < 2; ++g) {
    for (int a = 0; a < 2; ++a) {
      for (int m = 0; m < 3; ++m) {
        for (int w = 0; w < 3; ++w) {
          terms.push_back({"universal-" + kGenders[g] + "-" + kAges[a] + "-" + kMuscles[m] + "-" + kWeights[w] +
                               ".target.gz",
                           [=](const Setting& s) {
                             return genderWeight(s, g) * ageWeight(s, a) * muscleWeight(s, m) * weightWeight(s, w);
                           }});
        }
      }
    }
  }
  // Height and proportions exist for young adults only; they apply at every adult age.
  for (int g = 0; g < 2; ++g) {
    for (int m = 0; m < 3; ++m) {
      for (int w = 0; w < 3; ++w) {
        const std::string stem = kGenders[g] + "-young-" + kMuscles[m] + "-" + kWeights[w];
        auto base = [=](const Setting& s) { return genderWeight(s, g) * muscleWeight(s, m) * weightWeight(s, w); };
        terms.push_back({"height/" + stem + "-minheight.target.gz",
                         [=](const Setting& s) { return base(s) * std::max(0.0, 1.0 - 2.0 * s.height); }});
        terms.push_back({"height/" + stem + "-maxheight.target.gz",
                         [=](const Setting& s) { return base(s) * std::max(0.0, 2.0 * s.height - 1.0); }});
        terms.push_back({"proportions/" + stem + "-uncommonproportions.target.gz",
                         [=](const Setting& s) { return base(s) * std::max(0.0, 1.0 - 2.0 * s.proportions); }});
        terms.push_back({"proportions/" + stem + "-idealproportions.target.gz",
                         [=](const Setting& s) { return base(s) * std::max(0.0, 2.0 * s.proportions - 1.0); }});
      }
    }
  }
  return terms;
}

// Vertex index ranges of a named group in basemesh_vertex_groups.json.
std::vector<int> vertexGroup(const Json& groups, const std::string& name, const std::string& path) {
  if (!groups.contains(name)) throw fileError(path, "no vertex group '" + name + "'");
  std::vector<int> indices;
  for (const auto& range : groups.at(name)) {
    const int first = range.at(0).get<int>();
    const int last = range.at(1).get<int>();
    for (int i = first; i <= last; ++i) indices.push_back(i);
  }
  return indices;
}

// Lawson-Hanson non-negative least squares: min |A x - b| with x >= 0.
Eigen::VectorXd solveNnls(const Eigen::MatrixXd& A, const Eigen::VectorXd& b) {
  const Eigen::Index n = A.cols();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
  std::vector<bool> active(n, false);  // true = in the passive (free) set
  const double tolerance = 1e-12;
  auto solveFree = [&]() {
    std::vector<Eigen::Index> free;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (active[i]) free.push_back(i);
    }
    Eigen::MatrixXd Af(A.rows(), static_cast<Eigen::Index>(free.size()));
    for (std::size_t k = 0; k < free.size(); ++k) Af.col(static_cast<Eigen::Index>(k)) = A.col(free[k]);
    const Eigen::VectorXd zf = Af.colPivHouseholderQr().solve(b);
    Eigen::VectorXd z = Eigen::VectorXd::Zero(n);
    for (std::size_t k = 0; k < free.size(); ++k) z[free[k]] = zf[static_cast<Eigen::Index>(k)];
    return z;
  };
  for (int outer = 0; outer < 3 * n; ++outer) {
    const Eigen::VectorXd gradient = A.transpose() * (b - A * x);
    Eigen::Index best = -1;
    for (Eigen::Index i = 0; i < n; ++i) {
      if (!active[i] && gradient[i] > tolerance && (best < 0 || gradient[i] > gradient[best])) best = i;
    }
    if (best < 0) break;
    active[best] = true;
    Eigen::VectorXd z = solveFree();
    for (int inner = 0; inner < 3 * n; ++inner) {
      bool feasible = true;
      double alpha = 1.0;
      for (Eigen::Index i = 0; i < n; ++i) {
        if (active[i] && z[i] <= 0.0) {
          feasible = false;
          alpha = std::min(alpha, x[i] / (x[i] - z[i]));
        }
      }
      if (feasible) break;
      x += alpha * (z - x);
      for (Eigen::Index i = 0; i < n; ++i) {
        if (active[i] && x[i] <= tolerance) {
          active[i] = false;
          x[i] = 0.0;
        }
      }
      z = solveFree();
    }
    x = z;
  }
  return x;
}


// Re-poses the rest shape (rows: 3V vertices, then 3 per joint) and its shape directions with
// linear blend skinning so that the arms point along +-x and the legs along -y (SMPL's T pose):
// each limb joint gets the smallest rotation taking its bone onto that axis; joints without such
// a target keep their parent's orientation. Exact for the directions because LBS with fixed
// rotations is linear in the vertices and joints.
void poseIntoTPose(int V, const Eigen::MatrixXd& weights, Eigen::VectorXd* shape, Eigen::MatrixXd* dirs) {
  struct Bone {
    int joint, child;
    Eigen::Vector3d axis;
  };
  const std::array<Bone, 10> bones = {{{16, 18, Eigen::Vector3d::UnitX()},
                                       {18, 20, Eigen::Vector3d::UnitX()},
                                       {20, 22, Eigen::Vector3d::UnitX()},
                                       {17, 19, -Eigen::Vector3d::UnitX()},
                                       {19, 21, -Eigen::Vector3d::UnitX()},
                                       {21, 23, -Eigen::Vector3d::UnitX()},
                                       {1, 4, -Eigen::Vector3d::UnitY()},
                                       {2, 5, -Eigen::Vector3d::UnitY()},
                                       {4, 7, -Eigen::Vector3d::UnitY()},
                                       {5, 8, -Eigen::Vector3d::UnitY()}}};
  auto joint = [&](const Eigen::VectorXd& x, int j) { return Eigen::Vector3d(x.segment<3>(3 * V + 3 * j)); };
  std::array<Eigen::Matrix3d, kBodyJointCount> G;
  for (int j = 0; j < kBodyJointCount; ++j) {
    G[j] = j == 0 ? Eigen::Matrix3d::Identity() : G[kBodyJointParents[j]];
    for (const Bone& bone : bones) {
      if (bone.joint == j) {
        const Eigen::Vector3d d = joint(*shape, bone.child) - joint(*shape, j);
        G[j] = Eigen::Quaterniond::FromTwoVectors(d, bone.axis).toRotationMatrix();
      }
    }
  }
  // Posed joints (and their shape derivatives): J'_j = J'_p + G_p (J_j - J_p).
  auto poseJoints = [&](const Eigen::VectorXd& x) {
    std::array<Eigen::Vector3d, kBodyJointCount> posed;
    for (int j = 0; j < kBodyJointCount; ++j) {
      const int p = kBodyJointParents[j];
      posed[j] = p < 0 ? joint(x, j) : Eigen::Vector3d(posed[p] + G[p] * (joint(x, j) - joint(x, p)));
    }
    return posed;
  };
  // One column (the shape, or a direction): v' = sum_j w_j (G_j (v - J_j) + J'_j).
  auto poseColumn = [&](const Eigen::VectorXd& x) {
    const auto posed = poseJoints(x);
    Eigen::VectorXd out(x.size());
    for (int v = 0; v < V; ++v) {
      Eigen::Vector3d p = Eigen::Vector3d::Zero();
      for (int j = 0; j < kBodyJointCount; ++j) {
        if (weights(v, j) > 0) p += weights(v, j) * (G[j] * (x.segment<3>(3 * v) - joint(x, j)) + posed[j]);
      }
      out.segment<3>(3 * v) = p;
    }
    for (int j = 0; j < kBodyJointCount; ++j) out.segment<3>(3 * V + 3 * j) = posed[j];
    return out;
  };
  *shape = poseColumn(*shape);
  for (Eigen::Index k = 0; k < dirs->cols(); ++k) dirs->col(k) = poseColumn(dirs->col(k));
}

}  // namespace

std::vector<std::pair<std::string, NpyArray>> Mpfb2Converter::convert(const std::string& source_dir,
                                                                      Report* report) const {
  const Options& o = options_;
  if (o.shape_count < 1 || o.sample_count <= o.shape_count) {
    throw Error("Mpfb2Converter: need 1 <= shape_count < sample_count");
  }
  const std::string obj_path = source_dir + "/3dobjs/base.obj";
  const std::string groups_path = source_dir + "/mesh_metadata/basemesh_vertex_groups.json";
  const std::string rig_path = source_dir + "/rigs/standard/rig.game_engine.json";
  const std::string weights_path = source_dir + "/rigs/standard/weights.game_engine.json";
  const Obj obj = readObj(obj_path);
  const int all_vertices = static_cast<int>(obj.vertices.size());
  const Json groups = readJson(groups_path);
  const Json rig = readJson(rig_path);

  // Body vertices: those used by faces lying wholly in the 'body' group, re-indexed in order.
  std::vector<bool> in_body(all_vertices, false);
  for (const int i : vertexGroup(groups, "body", groups_path)) {
    if (i < 0 || i >= all_vertices) throw fileError(groups_path, "'body' group beyond the mesh");
    in_body[i] = true;
  }
  std::vector<std::vector<int>> body_faces;
  std::vector<int> new_index(all_vertices, -1);
  for (const auto& face : obj.faces) {
    if (std::all_of(face.begin(), face.end(), [&](int i) { return in_body[i]; })) {
      body_faces.push_back(face);
      for (const int i : face) new_index[i] = 0;
    }
  }
  std::vector<int> old_index;
  for (int i = 0; i < all_vertices; ++i) {
    if (new_index[i] == 0) {
      new_index[i] = static_cast<int>(old_index.size());
      old_index.push_back(i);
    }
  }
  const int V = static_cast<int>(old_index.size());
  if (V == 0) throw fileError(obj_path, "no body faces");

  // Joint cubes of the SMPL joints.
  std::array<std::vector<int>, kBodyJointCount> cubes;
  for (int j = 0; j < kBodyJointCount; ++j) {
    if (!rig.contains(kJointBones[j])) throw fileError(rig_path, std::string("no bone '") + kJointBones[j] + "'");
    const Json& head = rig.at(kJointBones[j]).at("head");
    if (head.value("strategy", "") != "CUBE") {
      throw fileError(rig_path, std::string("bone '") + kJointBones[j] + "' head is not a joint cube");
    }
    cubes[j] = vertexGroup(groups, head.at("cube_name").get<std::string>(), groups_path);
    for (const int i : cubes[j]) {
      if (i < 0 || i >= all_vertices) throw fileError(groups_path, "joint cube beyond the mesh");
    }
  }

  // Rows: 3 per body vertex, then 3 per joint (cube mean). Base positions and target matrix.
  const int rows = 3 * V + 3 * kBodyJointCount;
  Eigen::VectorXd base(rows);
  for (int v = 0; v < V; ++v) base.segment<3>(3 * v) = obj.vertices[old_index[v]];
  std::vector<std::vector<std::pair<int, double>>> cube_of_vertex(all_vertices);
  for (int j = 0; j < kBodyJointCount; ++j) {
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (const int i : cubes[j]) {
      mean += obj.vertices[i];
      cube_of_vertex[i].emplace_back(j, 1.0 / static_cast<double>(cubes[j].size()));
    }
    base.segment<3>(3 * V + 3 * j) = mean / static_cast<double>(cubes[j].size());
  }
  const std::vector<TargetTerm> terms = macroTerms();
  const int T = static_cast<int>(terms.size());
  Eigen::MatrixXd targets = Eigen::MatrixXd::Zero(rows, T);
  for (int t = 0; t < T; ++t) {
    const Target target = readTarget(source_dir + "/targets/macrodetails/" + terms[t].file, all_vertices);
    for (std::size_t k = 0; k < target.indices.size(); ++k) {
      const int i = target.indices[k];
      if (new_index[i] >= 0) targets.block<3, 1>(3 * new_index[i], t) += target.offsets[k];
      for (const auto& [j, share] : cube_of_vertex[i]) targets.block<3, 1>(3 * V + 3 * j, t) += share * target.offsets[k];
    }
  }

  // Random adult slider settings -> target weights (T x N).
  const int N = o.sample_count;
  Eigen::MatrixXd W(T, N);
  std::uint64_t state = o.seed;
  for (int s = 0; s < N; ++s) {
    Setting setting;
    setting.gender = uniform01(&state);
    setting.age = o.age_min + (o.age_max - o.age_min) * uniform01(&state);
    setting.muscle = uniform01(&state);
    setting.weight = uniform01(&state);
    setting.height = o.height_min + (o.height_max - o.height_min) * uniform01(&state);
    setting.proportions = uniform01(&state);
    double race_sum = 0.0;  // uniform on the simplex (normalised exponentials)
    for (double& r : setting.race) race_sum += (r = -std::log(1.0 - uniform01(&state)));
    for (double& r : setting.race) r /= race_sum;
    for (int t = 0; t < T; ++t) W(t, s) = terms[t].weight(setting);
  }
  const Eigen::VectorXd mean_weights = W.rowwise().mean();
  const Eigen::MatrixXd W_centred = W.colwise() - mean_weights;
  // PCA through the N x N Gram matrix of the centred offsets (targets * W_centred).
  const Eigen::MatrixXd targets_gram = targets.topRows(3 * V).transpose() * targets.topRows(3 * V);
  const Eigen::MatrixXd gram = W_centred.transpose() * targets_gram * W_centred;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(gram);
  const int K = o.shape_count;
  const double total_variance = eigen.eigenvalues().sum();

  const double kDecimetre = 0.1;
  Eigen::VectorXd mean_shape = (base + targets * mean_weights) * kDecimetre;
  Eigen::MatrixXd dirs(rows, K);
  std::vector<double> explained(K);
  for (int k = 0; k < K; ++k) {
    const Eigen::Index column = N - 1 - k;  // eigenvalues ascend
    explained[k] = eigen.eigenvalues()[column] / total_variance;
    dirs.col(k) = targets * (W_centred * eigen.eigenvectors().col(column)) * (kDecimetre / std::sqrt(N - 1.0));
  }
  // Signs: the first direction makes the body taller (top of head up, soles down); the others
  // have their largest vertex component positive.
  int top = 0, bottom = 0;
  for (int v = 0; v < V; ++v) {
    if (mean_shape[3 * v + 1] > mean_shape[3 * top + 1]) top = v;
    if (mean_shape[3 * v + 1] < mean_shape[3 * bottom + 1]) bottom = v;
  }
  for (int k = 0; k < K; ++k) {
    Eigen::Index largest = 0;
    dirs.col(k).head(3 * V).cwiseAbs().maxCoeff(&largest);
    const double sign = k == 0 ? dirs(3 * top + 1, k) - dirs(3 * bottom + 1, k) : dirs(largest, k);
    if (sign < 0) dirs.col(k) = -dirs.col(k);
  }
  // Origin at the mean shape's pelvis joint.
  const Eigen::Vector3d origin = mean_shape.segment<3>(3 * V);
  for (int r = 0; r < rows; r += 3) mean_shape.segment<3>(r) -= origin;

  // Skinning weights folded onto the SMPL segments.
  const Json weights_json = readJson(weights_path);
  Eigen::MatrixXd weights = Eigen::MatrixXd::Zero(V, kBodyJointCount);
  for (const auto& [bone, entries] : weights_json.at("weights").items()) {
    const int segment = segmentOfBone(bone);
    if (segment < 0) throw fileError(weights_path, "bone '" + bone + "' has no SMPL segment");
    for (const auto& entry : entries) {
      const int i = entry.at(0).get<int>();
      if (i < 0 || i >= all_vertices) throw fileError(weights_path, "vertex index beyond the mesh");
      if (new_index[i] >= 0) weights(new_index[i], segment) += entry.at(1).get<double>();
    }
  }
  // A few vertices carry stray weights (< 1 %) on the other side's limb (e.g. right toes on
  // ball_l); they would make the right foot twitch when the left leg moves, so they are dropped.
  int stray_fixed = 0;
  for (int v = 0; v < V; ++v) {
    double sum = weights.row(v).sum();
    if (!(sum > 0.0)) throw fileError(weights_path, "body vertex " + std::to_string(old_index[v]) + " has no weight");
    const double x = mean_shape[3 * v];
    if (std::abs(x) > 0.01) {
      double stray = 0.0;
      for (int j = 0; j < kBodyJointCount; ++j) {
        const bool left_joint = std::strncmp(kBodyJointNames[j], "left_", 5) == 0;
        const bool right_joint = std::strncmp(kBodyJointNames[j], "right_", 6) == 0;
        if ((x > 0 && right_joint) || (x < 0 && left_joint)) stray += weights(v, j);
      }
      if (stray > 0.0 && stray < 0.01 * sum) {
        for (int j = 0; j < kBodyJointCount; ++j) {
          const bool left_joint = std::strncmp(kBodyJointNames[j], "left_", 5) == 0;
          const bool right_joint = std::strncmp(kBodyJointNames[j], "right_", 6) == 0;
          if ((x > 0 && right_joint) || (x < 0 && left_joint)) weights(v, j) = 0.0;
        }
        sum = weights.row(v).sum();
        ++stray_fixed;
      }
    }
    weights.row(v) /= sum;
  }

  // SMPL's rest pose is a T pose; MakeHuman's is an A pose with legs apart. Re-pose limbs so
  // that zero rotations mean the same posture as in SMPL.
  poseIntoTPose(V, weights, &mean_shape, &dirs);

  // Joint regressor: non-negative weights over nearby body vertices whose weighted mean follows
  // the joint cube over the mean shape and each direction at +-regressor_shape_scale sigma.
  Eigen::MatrixXf regressor = Eigen::MatrixXf::Zero(kBodyJointCount, V);
  double max_joint_error = 0.0;
  std::ostringstream joint_log;
  for (int j = 0; j < kBodyJointCount; ++j) {
    const Eigen::Vector3d joint = mean_shape.segment<3>(3 * V + 3 * j);
    std::vector<std::pair<double, int>> by_distance(V);
    for (int v = 0; v < V; ++v) by_distance[v] = {(mean_shape.segment<3>(3 * v) - joint).norm(), v};
    std::sort(by_distance.begin(), by_distance.end());
    const double radius = o.regressor_radius_factor * by_distance.front().first + o.regressor_radius_margin;
    std::vector<int> candidates;
    for (const auto& [distance, v] : by_distance) {
      if (distance > radius || static_cast<int>(candidates.size()) >= o.regressor_max_candidates) break;
      candidates.push_back(v);
    }
    const int n = static_cast<int>(candidates.size());
    const int equations = 3 * (1 + K) + 1;
    Eigen::MatrixXd A = Eigen::MatrixXd::Zero(equations + n, n);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(equations + n);
    for (int c = 0; c < n; ++c) {
      const int v = candidates[c];
      A.block<3, 1>(0, c) = mean_shape.segment<3>(3 * v) - joint;
      for (int k = 0; k < K; ++k) {
        A.block<3, 1>(3 + 3 * k, c) =
            o.regressor_shape_scale * (dirs.block<3, 1>(3 * v, k) - dirs.block<3, 1>(3 * V + 3 * j, k));
      }
      A(equations - 1, c) = 1.0;
      A(equations + c, c) = std::sqrt(o.regressor_ridge);
    }
    b[equations - 1] = 1.0;
    const Eigen::VectorXd r = solveNnls(A, b);
    const double sum = r.sum();
    if (!(sum > 0.0)) throw Error("Mpfb2Converter: no joint regressor for " + std::string(kBodyJointNames[j]));
    double error = 0.0, rest_error = 0.0;
    for (int sign : {-1, 0, 1}) {
      for (int k = 0; k < (sign == 0 ? 1 : K); ++k) {
        Eigen::Vector3d estimate = Eigen::Vector3d::Zero();
        const double scale = sign * o.regressor_shape_scale;
        Eigen::Vector3d truth = joint + scale * dirs.block<3, 1>(3 * V + 3 * j, k);
        for (int c = 0; c < n; ++c) {
          const int v = candidates[c];
          estimate += (r[c] / sum) * (mean_shape.segment<3>(3 * v) + scale * dirs.block<3, 1>(3 * v, k));
        }
        error = std::max(error, (estimate - truth).norm());
        if (sign == 0) rest_error = (estimate - truth).norm();
      }
    }
    for (int c = 0; c < n; ++c) regressor(j, candidates[c]) = static_cast<float>(r[c] / sum);
    max_joint_error = std::max(max_joint_error, error);
    joint_log << "  " << kBodyJointNames[j] << ": " << n << " candidates, "
              << (r.array() > 0).count() << " used, error " << rest_error * 1000.0 << " mm at the mean shape, "
              << error * 1000.0 << " mm at most\n";
  }

  // Triangles (a b c, a c d, ...) oriented so that the enclosed signed volume is positive.
  std::vector<std::int32_t> faces;
  for (const auto& face : body_faces) {
    for (std::size_t k = 1; k + 1 < face.size(); ++k) {
      faces.push_back(new_index[face[0]]);
      faces.push_back(new_index[face[k]]);
      faces.push_back(new_index[face[k + 1]]);
    }
  }
  double volume = 0.0;
  for (std::size_t f = 0; f < faces.size(); f += 3) {
    const Eigen::Vector3d a = mean_shape.segment<3>(3 * faces[f]);
    const Eigen::Vector3d b2 = mean_shape.segment<3>(3 * faces[f + 1]);
    const Eigen::Vector3d c = mean_shape.segment<3>(3 * faces[f + 2]);
    volume += a.dot(b2.cross(c)) / 6.0;
  }
  if (volume < 0) {
    for (std::size_t f = 0; f < faces.size(); f += 3) std::swap(faces[f + 1], faces[f + 2]);
  }

  const auto Vs = static_cast<std::size_t>(V);
  std::vector<float> v_template(3 * Vs), shapedirs(3 * Vs * K), regressor_values(kBodyJointCount * Vs),
      weight_values(Vs * kBodyJointCount);
  for (std::size_t i = 0; i < 3 * Vs; ++i) {
    v_template[i] = static_cast<float>(mean_shape[static_cast<Eigen::Index>(i)]);
    for (int k = 0; k < K; ++k) shapedirs[i * K + k] = static_cast<float>(dirs(static_cast<Eigen::Index>(i), k));
  }
  for (int j = 0; j < kBodyJointCount; ++j) {
    for (int v = 0; v < V; ++v) regressor_values[j * Vs + v] = regressor(j, v);
  }
  for (int v = 0; v < V; ++v) {
    for (int j = 0; j < kBodyJointCount; ++j) weight_values[v * kBodyJointCount + j] = static_cast<float>(weights(v, j));
  }
  std::vector<std::int32_t> kintree(2 * kBodyJointCount);
  for (int j = 0; j < kBodyJointCount; ++j) {
    kintree[j] = kBodyJointParents[j];
    kintree[kBodyJointCount + j] = j;
  }
  const std::size_t F = faces.size() / 3;

  if (report) {
    report->vertex_count = V;
    report->triangle_count = static_cast<int>(F);
    report->explained_variance = explained;
    report->max_joint_error = max_joint_error;
    std::ostringstream text;
    text << V << " vertices, " << F << " triangles, " << T << " macro targets, " << N << " slider samples\n"
         << stray_fixed << " vertices had stray weights (< 1 %) on the other side's limbs, dropped\n"
         << "explained variance of the " << K << " shape directions:";
    double cumulative = 0.0;
    for (const double e : explained) {
      text << ' ' << std::round(e * 1000.0) / 10.0 << '%';
      cumulative += e;
    }
    text << " (total " << std::round(cumulative * 1000.0) / 10.0 << "%)\njoint regressor:\n" << joint_log.str();
    report->text = text.str();
  }

  std::vector<std::pair<std::string, NpyArray>> arrays;
  arrays.emplace_back("v_template", NpyArray::fromFloats({Vs, 3}, v_template));
  arrays.emplace_back("shapedirs", NpyArray::fromFloats({Vs, 3, static_cast<std::size_t>(K)}, shapedirs));
  arrays.emplace_back("posedirs", NpyArray::fromFloats({Vs, 3, 207}, std::vector<float>(Vs * 3 * 207, 0.0f)));
  arrays.emplace_back("J_regressor", NpyArray::fromFloats({kBodyJointCount, Vs}, regressor_values));
  arrays.emplace_back("weights", NpyArray::fromFloats({Vs, kBodyJointCount}, weight_values));
  arrays.emplace_back("kintree_table", NpyArray::fromInt32({2, kBodyJointCount}, kintree));
  arrays.emplace_back("f", NpyArray::fromInt32({F, 3}, faces));
  return arrays;
}

}  // namespace pf2
