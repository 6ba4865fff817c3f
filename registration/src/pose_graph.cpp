#include "pf2/registration/pose_graph.h"

#include <ceres/ceres.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

// Residual of one relative-pose measurement: the predicted T_i_j = T_w_i^-1 T_w_j against the
// measurement, translation difference and twice the vector part of the rotation difference
// (the rotation angle for small errors), each divided by its standard deviation.
struct RelativePoseError {
  RelativePoseError(const Eigen::Isometry3d& T_i_j, double translation_sigma, double rotation_sigma)
      : t_ij(T_i_j.translation()),
        q_ij(Eigen::Quaterniond(T_i_j.rotation()).normalized()),
        inv_sigma_t(1.0 / translation_sigma),
        inv_sigma_r(1.0 / rotation_sigma) {}

  template <typename T>
  bool operator()(const T* t_i_ptr, const T* q_i_ptr, const T* t_j_ptr, const T* q_j_ptr,
                  T* residual_ptr) const {
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t_i(t_i_ptr), t_j(t_j_ptr);
    const Eigen::Map<const Eigen::Quaternion<T>> q_i(q_i_ptr), q_j(q_j_ptr);
    const Eigen::Quaternion<T> q_i_inv = q_i.conjugate();
    const Eigen::Matrix<T, 3, 1> t_pred = q_i_inv * (t_j - t_i);
    const Eigen::Quaternion<T> q_pred = q_i_inv * q_j;
    const Eigen::Quaternion<T> q_err = q_ij.cast<T>().conjugate() * q_pred;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> residual(residual_ptr);
    residual.template head<3>() = (t_pred - t_ij.cast<T>()) * T(inv_sigma_t);
    residual.template tail<3>() = T(2.0) * q_err.vec() * T(inv_sigma_r);
    return true;
  }

  Eigen::Vector3d t_ij;
  Eigen::Quaterniond q_ij;
  double inv_sigma_t, inv_sigma_r;
};

}  // namespace

PoseGraph::PoseGraph() : PoseGraph(Options()) {}
PoseGraph::PoseGraph(const Options& options) : options_(options) {}

void PoseGraph::addNode(int id, const Eigen::Isometry3d& T_w_n) {
  nodes_[id] = Node{T_w_n.translation(), Eigen::Quaterniond(T_w_n.rotation()).normalized()};
  if (fixed_id_ < 0) fixed_id_ = id;
}

void PoseGraph::addEdge(const Edge& edge) {
  if (!hasNode(edge.from) || !hasNode(edge.to))
    throw Error("PoseGraph::addEdge: unknown node in edge " + std::to_string(edge.from) + " -> " +
                std::to_string(edge.to));
  if (!(edge.translation_sigma > 0.0) || !(edge.rotation_sigma > 0.0))
    throw Error("PoseGraph::addEdge: sigmas must be positive");
  // Ceres rejects a residual on the same parameter blocks twice; a self-edge also carries no
  // information.
  if (edge.from == edge.to)
    throw Error("PoseGraph::addEdge: edge from node " + std::to_string(edge.from) + " to itself");
  edges_.push_back(edge);
}

PoseGraph::Summary PoseGraph::optimize() {
  const std::map<int, Node> start = nodes_;
  Summary summary = solve();
  const double initial_cost = summary.initial_cost;
  for (int round = 0; round < options_.max_rejection_rounds; ++round) {
    Edge* worst = nullptr;
    double worst_residual = options_.loop_outlier_sigmas;
    for (Edge& e : edges_) {
      if (!e.loop || e.rejected) continue;
      const double r = normalisedResidual(e);
      if (r > worst_residual) {
        worst_residual = r;
        worst = &e;
      }
    }
    if (!worst) break;
    worst->rejected = true;
    ++summary.rejected_loops;
    nodes_ = start;  // the rejected loop must not leave its pull behind
    const int rejected = summary.rejected_loops;
    summary = solve();
    summary.rejected_loops = rejected;
  }
  summary.initial_cost = initial_cost;
  return summary;
}

double PoseGraph::normalisedResidual(const Edge& e) const {
  const Node& a = nodes_.at(e.from);
  const Node& b = nodes_.at(e.to);
  const RelativePoseError error(e.T_from_to, e.translation_sigma, e.rotation_sigma);
  Eigen::Matrix<double, 6, 1> r;
  error(a.t.data(), a.q.coeffs().data(), b.t.data(), b.q.coeffs().data(), r.data());
  return r.norm();
}

PoseGraph::Summary PoseGraph::solve() {
  Summary summary;
  ceres::Problem problem;
  for (const Edge& e : edges_) {
    if (e.rejected) continue;
    Node& a = nodes_.at(e.from);
    Node& b = nodes_.at(e.to);
    ceres::CostFunction* cost =
        new ceres::AutoDiffCostFunction<RelativePoseError, 6, 3, 4, 3, 4>(
            new RelativePoseError(e.T_from_to, e.translation_sigma, e.rotation_sigma));
    problem.AddResidualBlock(cost, nullptr, a.t.data(), a.q.coeffs().data(), b.t.data(),
                             b.q.coeffs().data());
  }
  if (problem.NumResidualBlocks() == 0) {
    summary.converged = true;
    return summary;
  }
  for (auto& [id, node] : nodes_) {
    if (!problem.HasParameterBlock(node.q.coeffs().data())) continue;
    problem.SetManifold(node.q.coeffs().data(), new ceres::EigenQuaternionManifold);
    if (id == fixed_id_) {
      problem.SetParameterBlockConstant(node.t.data());
      problem.SetParameterBlockConstant(node.q.coeffs().data());
    }
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.max_num_iterations = options_.max_iterations;
  solver.num_threads = options_.threads;
  solver.logging_type = ceres::SILENT;
  std::string why;
  if (!solver.IsValid(&why)) solver.linear_solver_type = ceres::DENSE_QR;  // no sparse library
  ceres::Solver::Summary result;
  ceres::Solve(solver, &problem, &result);
  summary.converged = result.termination_type == ceres::CONVERGENCE;
  summary.iterations = static_cast<int>(result.iterations.size());
  summary.initial_cost = result.initial_cost;
  summary.final_cost = result.final_cost;
  for (auto& [id, node] : nodes_) node.q.normalize();
  return summary;
}

Eigen::Isometry3d PoseGraph::pose(int id) const {
  const auto it = nodes_.find(id);
  if (it == nodes_.end()) throw Error("PoseGraph: no node " + std::to_string(id));
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = it->second.q.toRotationMatrix();
  T.translation() = it->second.t;
  return T;
}

std::map<int, Eigen::Isometry3d> PoseGraph::poses() const {
  std::map<int, Eigen::Isometry3d> out;
  for (const auto& entry : nodes_) out.emplace(entry.first, pose(entry.first));
  return out;
}

}  // namespace pf2
