#pragma once
// Keyframe pose graph optimised with Ceres: nodes are T_w_k (translation + unit quaternion on
// Ceres' EigenQuaternionManifold), edges are measured relative poses T_i_j with isotropic
// translation and rotation standard deviations, squared loss.
// Wrong loops: a robust kernel on loop edges would also switch off the right loops (after a long
// drift a correct loop is tens of sigmas off before optimisation), so instead the graph is solved
// with all loops, and a loop edge still far off afterwards (it disagrees with the rest) is
// rejected and the graph solved again without it.
// The first node added is held fixed (it defines the world frame).
#include <map>
#include <vector>

#include <Eigen/Geometry>

namespace pf2 {

class PoseGraph {
 public:
  struct Options {
    int max_iterations = 100;        // Levenberg-Marquardt iterations per optimize()
    double loop_outlier_sigmas = 5.0;  // loop edge residual (in sigmas) that rejects it
    int max_rejection_rounds = 3;      // re-solves after rejecting the worst loop edge
    int threads = 1;                 // Ceres threads (the back-end runs beside tracking)
  };

  struct Edge {
    int from = -1;
    int to = -1;
    Eigen::Isometry3d T_from_to = Eigen::Isometry3d::Identity();  // measured
    double translation_sigma = 0.01;  // metres
    double rotation_sigma = 0.01;     // radians
    bool loop = false;                // loop edges may be rejected as outliers
    bool rejected = false;            // set by optimize(); a rejected edge is ignored after
  };

  struct Summary {
    bool converged = false;
    int iterations = 0;
    double initial_cost = 0.0;  // Ceres cost (half the sum of squared normalised residuals)
    double final_cost = 0.0;
    int rejected_loops = 0;     // loop edges rejected by this call
  };

  PoseGraph();
  explicit PoseGraph(const Options& options);

  // Adds (or re-initialises) node `id` at T_w_n. NOT thread safe (nor any other method).
  void addNode(int id, const Eigen::Isometry3d& T_w_n);
  // Throws pf2::Error when an end node is unknown or a sigma is not positive.
  void addEdge(const Edge& edge);
  bool hasNode(int id) const { return nodes_.count(id) > 0; }
  size_t nodeCount() const { return nodes_.size(); }
  const std::vector<Edge>& edges() const { return edges_; }

  Summary optimize();
  Eigen::Isometry3d pose(int id) const;  // throws pf2::Error for an unknown id
  std::map<int, Eigen::Isometry3d> poses() const;

 private:
  struct Node {
    Eigen::Vector3d t;
    Eigen::Quaterniond q;
  };
  Summary solve();
  double normalisedResidual(const Edge& edge) const;

  Options options_;
  std::map<int, Node> nodes_;
  int fixed_id_ = -1;
  std::vector<Edge> edges_;
};

}  // namespace pf2
