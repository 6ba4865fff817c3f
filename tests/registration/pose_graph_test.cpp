#include "pf2/registration/pose_graph.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/core/pose.h"

namespace pf2 {
namespace {

Eigen::Isometry3d motion(double x, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, 0, 0);
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitY()).toRotationMatrix();
  return T;
}

double rmsPositionError(const std::vector<Eigen::Isometry3d>& truth, const PoseGraph& graph) {
  double sum = 0.0;
  for (size_t i = 0; i < truth.size(); ++i)
    sum += (graph.pose(static_cast<int>(i)).translation() - truth[i].translation()).squaredNorm();
  return std::sqrt(sum / truth.size());
}

// A circle of 40 poses (9 degrees per step) measured with a biased, noisy odometry.
void driftedCircle(PoseGraph* graph_ptr, std::vector<Eigen::Isometry3d>* truth_out) {
  const int n = 40;
  const Eigen::Isometry3d step = motion(0.3, 2 * M_PI / n);
  std::vector<Eigen::Isometry3d> truth{Eigen::Isometry3d::Identity()};
  for (int i = 1; i < n; ++i) truth.push_back(truth.back() * step);

  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.002);
  PoseGraph& graph = *graph_ptr;
  Eigen::Isometry3d drifted = Eigen::Isometry3d::Identity();
  graph.addNode(0, drifted);
  for (int i = 1; i < n; ++i) {
    // 0.4 degrees of yaw and 4 mm of extra length per step, plus noise.
    Eigen::Isometry3d measured = truth[i - 1].inverse() * truth[i] * motion(0.004, 0.007);
    measured.translation() += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    drifted = drifted * measured;
    graph.addNode(i, drifted);
    PoseGraph::Edge edge;
    edge.from = i - 1;
    edge.to = i;
    edge.T_from_to = measured;
    graph.addEdge(edge);
  }
  *truth_out = truth;
}

PoseGraph::Edge trueLoop(const std::vector<Eigen::Isometry3d>& truth, int from, int to) {
  PoseGraph::Edge loop;
  loop.from = from;
  loop.to = to;
  loop.T_from_to = truth[from].inverse() * truth[to];
  loop.loop = true;
  return loop;
}

// Closed by one loop edge from the last pose back to the first.
TEST(PoseGraph, ClosesASyntheticLoopWithKnownDrift) {
  PoseGraph graph;
  std::vector<Eigen::Isometry3d> truth;
  driftedCircle(&graph, &truth);
  const int n = static_cast<int>(truth.size());
  const double before = rmsPositionError(truth, graph);
  graph.addEdge(trueLoop(truth, 0, n - 1));
  const PoseGraph::Summary summary = graph.optimize();
  EXPECT_EQ(summary.rejected_loops, 0);
  const double after = rmsPositionError(truth, graph);

  EXPECT_GT(before, 0.3);  // the drift is real: tens of centimetres
  EXPECT_LT(after, 0.1 * before);
  EXPECT_LT(summary.final_cost, summary.initial_cost);
  // The first node defines the world frame and stays put.
  EXPECT_LT((graph.pose(0).translation()).norm(), 1e-12);
  EXPECT_LT(rotationAngle(graph.pose(0).rotation()), 1e-12);
}

// Two right loops and one wrong one (place recognition confused two similar places).
TEST(PoseGraph, RejectsALoopThatDisagreesWithTheOthers) {
  PoseGraph graph;
  std::vector<Eigen::Isometry3d> truth;
  driftedCircle(&graph, &truth);
  const int n = static_cast<int>(truth.size());
  const double before = rmsPositionError(truth, graph);
  graph.addEdge(trueLoop(truth, 0, n - 1));
  graph.addEdge(trueLoop(truth, 1, n - 2));
  PoseGraph::Edge wrong = trueLoop(truth, 5, 25);
  wrong.T_from_to = Eigen::Isometry3d::Identity();  // claims node 25 is where node 5 is
  graph.addEdge(wrong);
  const PoseGraph::Summary summary = graph.optimize();
  EXPECT_EQ(summary.rejected_loops, 1);
  EXPECT_TRUE(graph.edges().back().rejected);
  EXPECT_LT(rmsPositionError(truth, graph), 0.1 * before);
}

TEST(PoseGraph, ConsistentGraphStaysWhereItIs) {
  PoseGraph graph;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  graph.addNode(0, T);
  for (int i = 1; i < 5; ++i) {
    T = T * motion(0.2, 0.1);
    graph.addNode(i, T);
    PoseGraph::Edge edge;
    edge.from = i - 1;
    edge.to = i;
    edge.T_from_to = motion(0.2, 0.1);
    graph.addEdge(edge);
  }
  graph.optimize();
  EXPECT_LT((graph.pose(4).translation() - T.translation()).norm(), 1e-9);
}

TEST(PoseGraph, RejectsBadEdges) {
  PoseGraph graph;
  graph.addNode(0, Eigen::Isometry3d::Identity());
  PoseGraph::Edge edge;
  edge.from = 0;
  edge.to = 1;
  EXPECT_THROW(graph.addEdge(edge), Error);
  graph.addNode(1, Eigen::Isometry3d::Identity());
  edge.translation_sigma = 0.0;
  EXPECT_THROW(graph.addEdge(edge), Error);
  EXPECT_THROW(graph.pose(7), Error);
}

}  // namespace
}  // namespace pf2
