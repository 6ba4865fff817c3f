#include "pf2/registration/pose_graph_backend.h"

#include <atomic>
#include <cmath>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/core/pose.h"
#include "rendered_scene.h"

namespace pf2 {
namespace {

// The camera turns on the spot in the middle of the rendered room, 15 degrees per keyframe, a
// full turn and three more keyframes that revisit the first three places (3 cm off). Odometry
// edges are given with a known bias (0.46 degrees of yaw per keyframe, 12 degrees at the end), so
// the only way back to the truth is loop closing.
TEST(PoseGraphBackend, ClosesALoopFoundByAppearanceInItsOwnThread) {
  const CameraIntrinsics k = CameraIntrinsics::tumFreiburg1().scaled(0.5);
  const int n = 27;
  std::vector<Eigen::Isometry3d> truth;
  for (int i = 0; i < n; ++i) {
    const double shift = i >= 24 ? 0.03 : 0.0;
    truth.push_back(test::cameraPose(shift, -0.2, 0.75, 0.05, i * M_PI / 12.0, 0.0));
  }
  Eigen::Isometry3d bias = Eigen::Isometry3d::Identity();
  bias.linear() = Eigen::AngleAxisd(0.008, Eigen::Vector3d::UnitY()).toRotationMatrix();
  bias.translation() = Eigen::Vector3d(0.003, 0.0, 0.002);

  RgbdOdometry odometry;
  KeyframeMap map;
  LoopDetector loops;
  PoseGraphBackend backend(PoseGraphBackend::Options(), &map, &loops);
  std::atomic<int> callbacks{0};
  backend.setCorrectionCallback(
      [&](const std::map<int, Eigen::Isometry3d>& poses) {
        if (poses.size() > 0) ++callbacks;
      });
  backend.start();

  std::vector<Eigen::Isometry3d> drifted;
  for (int i = 0; i < n; ++i) {
    OdometryFrame frame = odometry.prepare(test::renderRoom(truth[i], k, i));
    odometry.makeReference(&frame);
    const Eigen::Isometry3d measured =
        i == 0 ? Eigen::Isometry3d::Identity() : truth[i - 1].inverse() * truth[i] * bias;
    drifted.push_back(i == 0 ? truth[0] : drifted.back() * measured);
    const int id = map.add(makeKeyframe(frame), drifted.back());
    ASSERT_EQ(id, i);
    loops.add(id, frame.descriptors);
    backend.addKeyframe(id, id - 1, measured);
  }
  backend.waitIdle();
  backend.stop();
  // The camera turns on the spot, so the drift is in orientation: RMS angle error, degrees.
  auto rms = [&](const std::map<int, Eigen::Isometry3d>& poses) {
    double sum = 0.0;
    for (int i = 0; i < n; ++i) {
      const double a = rotationAngle(poses.at(i).rotation().transpose() * truth[i].rotation());
      sum += a * a;
    }
    return std::sqrt(sum / n) * 180.0 / M_PI;
  };
  std::map<int, Eigen::Isometry3d> before;
  for (int i = 0; i < n; ++i) before[i] = drifted[i];
  const std::vector<PoseGraphBackend::LoopClosure> closures = backend.loopClosures();
  ASSERT_FALSE(closures.empty());
  for (const auto& c : closures) {
    // Each accepted loop joins views that really overlap (under 60 degrees apart), at least
    // min_loop_gap keyframes apart, with the right relative pose.
    const Eigen::Isometry3d expected = truth[c.from].inverse() * truth[c.to];
    EXPECT_GE(c.to - c.from, PoseGraphBackend::Options().min_loop_gap);
    EXPECT_LT(rotationAngle(expected.rotation()), M_PI / 3);
    EXPECT_LT((c.T_from_to.translation() - expected.translation()).norm(), 0.005);
    EXPECT_LT(rotationAngle((c.T_from_to.inverse() * expected).rotation()), 0.005);
  }
  EXPECT_GT(backend.optimisations(), 0);
  EXPECT_EQ(callbacks.load(), backend.optimisations());
  EXPECT_GT(map.revision(), 0u);
  const double error_before = rms(before), error_after = rms(map.poses());
  EXPECT_GT(error_before, 5.0);
  EXPECT_LT(error_after, 0.1 * error_before);
  std::printf("keyframe orientation RMS: %.3f deg before loop closing, %.3f deg after (%zu loops)\n",
              error_before, error_after, closures.size());
}

// A new keyframe that sees only a strip of the scene (a person covering the rest) aligns onto
// an old full view with a high inlier ratio whatever it slides to, since only its own samples
// count. Aligning the old view back onto the strip finds little overlap: no loop.
TEST(PoseGraphBackend, LoopVerificationCountsOverlapOnBothSides) {
  const CameraIntrinsics k = CameraIntrinsics::tumFreiburg1().scaled(0.5);
  const Eigen::Isometry3d T_w_0 = test::cameraPose(0.0, -0.2, 0.75, 0.05, 0.0, 0.0);
  const Eigen::Isometry3d T_w_1 = test::cameraPose(0.02, -0.2, 0.73, 0.05, 0.03, 0.0);
  RgbdOdometry odometry;
  Frame strip = test::renderRoom(T_w_1, k, 1);
  strip.depth.rowRange(0, strip.depth.rows * 3 / 4).setTo(0.0f);  // 25 % of the rows left
  auto run = [&](const PoseGraphBackend::Options& options, const Frame& second) {
    KeyframeMap map;
    LoopDetector loops;
    PoseGraphBackend backend(options, &map, &loops);
    const Frame frames[2] = {test::renderRoom(T_w_0, k, 0), second};
    for (int i = 0; i < 2; ++i) {
      OdometryFrame frame = odometry.prepare(frames[i]);
      odometry.makeReference(&frame);
      // No odometry edge between them: the loop is the only link the back-end could make.
      const int id = map.add(makeKeyframe(frame), Eigen::Isometry3d::Identity());
      loops.add(id, frame.descriptors);
      backend.addKeyframe(id, -1, Eigen::Isometry3d::Identity());
    }
    backend.processPending();
    return backend.loopClosures();
  };
  PoseGraphBackend::Options options;
  options.min_loop_gap = 1;
  EXPECT_TRUE(run(options, strip).empty());

  // The one-sided check alone (the old acceptance rule) passes it; the reverse one does not.
  OdometryFrame full = odometry.prepare(test::renderRoom(T_w_0, k, 0));
  odometry.makeReference(&full);
  OdometryFrame part = odometry.prepare(strip);
  odometry.makeReference(&part);
  const OdometryResult forward = odometry.estimateWithoutPrior(full, &part);
  ASSERT_TRUE(forward.valid);
  EXPECT_GE(forward.dense.inlier_ratio, options.min_loop_inlier_ratio);
  const DenseAlignment reverse = odometry.refine(part, full, forward.T_ref_cur.inverse());
  EXPECT_LT(reverse.inlier_ratio, options.min_loop_reverse_inlier_ratio);

  // The whole second view is accepted, with the right pose.
  const std::vector<PoseGraphBackend::LoopClosure> whole = run(options, test::renderRoom(T_w_1, k, 1));
  ASSERT_EQ(whole.size(), 1u);
  const Eigen::Isometry3d expected = T_w_0.inverse() * T_w_1;
  EXPECT_LT((whole[0].T_from_to.translation() - expected.translation()).norm(), 0.003);
}

// Eight keyframes along an arc, 5 degrees and 2 cm apart: too few for a loop (min_loop_gap),
// and the chain's odometry edges carry a bias (0.6 degrees of yaw and 4 mm per keyframe). Only
// the local window's edges (each new keyframe aligned onto its near predecessors) pull the
// keyframes back; without them nothing is optimised.
TEST(PoseGraphBackend, LocalWindowEdgesCorrectChainDriftWithoutALoop) {
  const CameraIntrinsics k = CameraIntrinsics::tumFreiburg1().scaled(0.5);
  const int n = 8;
  std::vector<Eigen::Isometry3d> truth;
  for (int i = 0; i < n; ++i) truth.push_back(test::cameraPose(0.02 * i, -0.2, 0.75, 0.05, i * 0.087, 0.0));
  Eigen::Isometry3d bias = Eigen::Isometry3d::Identity();
  bias.linear() = Eigen::AngleAxisd(0.0105, Eigen::Vector3d::UnitY()).toRotationMatrix();
  bias.translation() = Eigen::Vector3d(0.004, 0.0, 0.0);
  RgbdOdometry odometry;
  std::vector<OdometryFrame> frames;
  for (int i = 0; i < n; ++i) {
    frames.push_back(odometry.prepare(test::renderRoom(truth[i], k, i)));
    odometry.makeReference(&frames.back());
  }
  // Keyframe pose errors (RMS, translation in metres and rotation in radians) after the run.
  auto run = [&](const PoseGraphBackend::Options& options, int* local_edges) {
    KeyframeMap map;
    LoopDetector loops;
    PoseGraphBackend backend(options, &map, &loops);
    Eigen::Isometry3d drifted = truth[0];
    for (int i = 0; i < n; ++i) {
      const Eigen::Isometry3d measured = i == 0 ? Eigen::Isometry3d::Identity() : truth[i - 1].inverse() * truth[i] * bias;
      drifted = drifted * measured;
      const int id = map.add(makeKeyframe(frames[i]), drifted);
      loops.add(id, frames[i].descriptors);
      backend.addKeyframe(id, id - 1, measured);
      backend.processPending();
    }
    EXPECT_TRUE(backend.loopClosures().empty());
    *local_edges = backend.localEdges();
    double t = 0.0, r = 0.0;
    for (int i = 0; i < n; ++i) {
      const Eigen::Isometry3d error = truth[0] * map.pose(0).inverse() * map.pose(i) * truth[i].inverse();
      t += error.translation().squaredNorm();
      r += std::pow(rotationAngle(error.rotation()), 2);
    }
    return std::make_pair(std::sqrt(t / n), std::sqrt(r / n));
  };
  PoseGraphBackend::Options chain_only;
  chain_only.local_edges = 0;
  int edges = 0;
  const auto before = run(chain_only, &edges);
  EXPECT_EQ(edges, 0);
  const auto after = run(PoseGraphBackend::Options(), &edges);
  EXPECT_GE(edges, n);  // about local_edges per keyframe once the window has filled
  EXPECT_GT(before.second, 0.015);
  EXPECT_LT(after.second, 0.25 * before.second);
  EXPECT_LT(after.first, 0.25 * before.first);
  std::printf("chain drift: %.1f mm / %.2f deg RMS; with %d local edges %.1f mm / %.2f deg\n",
              1000 * before.first, before.second * 180 / M_PI, edges, 1000 * after.first,
              after.second * 180 / M_PI);
}

TEST(KeyframeMap, AddRelativeFollowsACorrectionOfItsReference) {
  KeyframeMap map;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  map.add(Keyframe(), T);
  T.translation() = Eigen::Vector3d(1, 0, 0);
  map.add(Keyframe(), T);
  // The back-end moves keyframe 1 while tracking measures a new keyframe 0.1 m in front of it.
  Eigen::Isometry3d moved = T;
  moved.translation().y() = 0.3;
  moved.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  map.updatePoses({{1, moved}});
  Eigen::Isometry3d T_1_new = Eigen::Isometry3d::Identity();
  T_1_new.translation() = Eigen::Vector3d(0, 0, 0.1);
  EXPECT_EQ(map.addRelative(Keyframe(), 1, T_1_new), 2);
  EXPECT_TRUE(map.pose(2).isApprox(moved * T_1_new, 1e-12));
  EXPECT_THROW(map.addRelative(Keyframe(), 7, T_1_new), Error);
}

TEST(KeyframeMap, CorrectionsCarryNewerKeyframesAlong) {
  KeyframeMap map;
  Keyframe k;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    T.translation() = Eigen::Vector3d(i, 0, 0);
    EXPECT_EQ(map.add(k, T), i);
  }
  // The graph knew keyframes 0 and 1 and moved 1 by +0.5 m in y; 2 came later.
  Eigen::Isometry3d moved = map.pose(1);
  moved.translation().y() += 0.5;
  map.updatePoses({{0, map.pose(0)}, {1, moved}});
  EXPECT_NEAR(map.pose(2).translation().y(), 0.5, 1e-12);
  EXPECT_NEAR(map.pose(2).translation().x(), 2.0, 1e-12);
  EXPECT_EQ(map.revision(), 1u);
  EXPECT_THROW(map.keyframe(3), Error);
}

}  // namespace
}  // namespace pf2
