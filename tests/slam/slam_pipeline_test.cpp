// The whole pipeline as pf2_slam runs it, with people and the map on: detector (the ground-truth
// oracle, which needs no model files) -> Dual-BBox filter with its additions -> tracker -> human
// tracks -> TSDF map, on a small generated sequence (half resolution, 60 frames, xyz camera, three
// people). The same run without person removal shows what removal buys in the map.
#include <set>

#include <gtest/gtest.h>

#include "pf2/core/pose.h"
#include "pf2/eval/trajectory_metrics.h"
#include "pf2/humans/human_track.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/io/tum_sequence.h"
#include "pf2/slam/slam_system.h"
#include "pf2/surface/map_evaluator.h"
#include "pf2/surface/triangle_mesh.h"
#include "pf2/synth/synthetic_sequence.h"

namespace pf2 {
namespace {

const std::string& sequenceFolder() {
  static const std::string folder = [] {
    SyntheticSequence::Options options;
    options.frames = 60;
    options.people = 3;
    options.intrinsics = CameraIntrinsics::tumFreiburg3().scaled(0.5);
    const std::string out = testing::TempDir() + "pf2_pipeline_sequence";
    SyntheticSequence(options).writeTumFolder(out);
    return out;
  }();
  return folder;
}

struct RunFigures {
  SlamRunSummary summary;
  double ate = 0.0;
  MapQuality map;
  std::set<int> human_ids;
};

RunFigures runPipeline(const std::string& detector, const std::string& name) {
  SlamOptions options;
  options.detector = detector;
  options.progress = false;
  options.tracker.asynchronous_backend = false;
  options.mapper.build_occupancy = false;  // the TSDF mesh is what is scored
  const std::string run = testing::TempDir() + name;
  const std::string& folder = sequenceFolder();
  RunFigures figures;
  figures.summary = SlamSystem(options).run(TumSequence(folder), folder, run);
  const Trajectory truth = readTrajectory(folder + "/groundtruth.txt");
  const Trajectory estimate = readTrajectory(run + "/trajectory.txt");
  figures.ate = computeAte(truth, estimate).translation.rmse;
  // The map is in the first camera's frame: moved into the room's by the first pose's truth.
  const Eigen::Isometry3d T_gt_est = truth.front().T_w_c * estimate.front().T_w_c.inverse();
  TriangleMesh map = loadMeshPly(run + "/map.ply");
  for (Eigen::Vector3f& v : map.vertices) v = (T_gt_est * v.cast<double>()).cast<float>();
  MapEvaluator evaluator(loadMeshPly(folder + "/gt/static_scene.ply"), MapEvaluator::Options());
  evaluator.markAllSeen();
  figures.map = evaluator.evaluate(map);
  if (detector != "none") {
    for (const HumanTrack& track : readHumanTracks(run + "/humans.txt")) figures.human_ids.insert(track.id);
  }
  return figures;
}

TEST(SlamPipeline, PeopleLeaveTheMapAndGetTracksWhileTheCameraIsTracked) {
  const RunFigures with = runPipeline("gt", "pf2_pipeline_people_removed");
  const RunFigures without = runPipeline("none", "pf2_pipeline_people_kept");
  std::printf("removed: ATE %.1f mm, %zu map vertices, %zu ghosts, median %.1f mm, %zu people; "
              "kept: ATE %.1f mm, %zu ghosts of %zu\n",
              1000 * with.ate, with.map.map_vertices, with.map.ghost_vertices, 1000 * with.map.median,
              with.human_ids.size(), 1000 * without.ate, without.map.ghost_vertices, without.map.map_vertices);
  EXPECT_EQ(with.summary.frames, 60);
  EXPECT_EQ(with.summary.lost, 0);
  EXPECT_LT(with.ate, 0.01);
  EXPECT_GE(with.human_ids.size(), 2u);
  ASSERT_GT(with.map.map_vertices, 5000u);
  EXPECT_LT(with.map.median, 0.01);
  EXPECT_LT(with.map.ghost_vertices, 0.01 * with.map.map_vertices);
  // Without removal the people are fused into the map (and drag the camera along).
  EXPECT_GT(without.map.ghost_vertices, 5 * std::max<std::size_t>(with.map.ghost_vertices, 100));
}

}  // namespace
}  // namespace pf2
