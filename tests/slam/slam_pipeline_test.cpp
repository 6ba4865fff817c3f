// The whole pipeline as pf2_slam runs it, with people and the map on: detector (the ground-truth
// oracle, which needs no model files) -> Dual-BBox filter with its additions -> tracker -> human
// tracks -> TSDF map, on a small generated sequence (half resolution, 60 frames, xyz camera, three
// people). The same run without person removal shows what removal buys in the map.
#include <set>

#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include "pf2/core/pose.h"
#include "pf2/detection/gt_detector.h"
#include "pf2/eval/trajectory_metrics.h"
#include "pf2/humans/human_track.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/io/frame_streams.h"
#include "pf2/io/tum_sequence.h"
#include "pf2/slam/slam_runner.h"
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

// The ground truth's people with their masks, seen only from frame `first` on, each with 17
// keypoints on their mask (as a pose network gives them): a detector that finds everyone late.
class LateDetector : public HumanDetector {
 public:
  LateDetector(const std::string& folder, int first) : gt_(gtOptions(folder)), first_(first) {}
  std::string name() const override { return "late"; }
  Detections detect(const Frame& frame) override {
    Detections detections = gt_.detect(frame);
    if (frame_++ < first_) detections.people.clear();
    for (PersonDetection& person : detections.people) {
      std::vector<cv::Point> pixels;
      cv::findNonZero(person.mask, pixels);
      if (pixels.empty()) continue;
      for (int k = 0; k < 17; ++k) {
        const cv::Point& p = pixels[(pixels.size() - 1) * k / 16];
        person.keypoints.push_back({static_cast<float>(p.x), static_cast<float>(p.y), 0.9f});
      }
    }
    return detections;
  }

 private:
  static GtDetector::Options gtOptions(const std::string& folder) {
    GtDetector::Options options;
    options.gt_folder = folder + "/gt";
    options.provide_mask = true;
    return options;
  }
  GtDetector gt_;
  int first_;
  int frame_ = 0;
};

// Person pixels with depth (ground truth) removed in the masks of frames [from, to), and all of them.
std::pair<long, long> personPixelsRemoved(const std::string& folder, const std::string& run, int from, int to) {
  const TumSequence sequence(folder);
  long removed = 0, all = 0;
  for (int i = from; i < to; ++i) {
    const Frame frame = sequence.frame(i);
    char name[64];
    std::snprintf(name, sizeof(name), "%.6f.png", frame.timestamp);
    const cv::Mat person = cv::imread(folder + "/gt/masks/" + name, cv::IMREAD_UNCHANGED) > 0;
    const cv::Mat mask = cv::imread(run + "/masks/" + name, cv::IMREAD_UNCHANGED) > 0;
    const cv::Mat measured = person & (frame.depth > 0.f);
    all += cv::countNonZero(measured);
    removed += cv::countNonZero(measured & mask);
  }
  return {removed, all};
}

TEST(SlamPipeline, PeopleFoundLateLeaveTheMapsFramesBeforeButNotTheTrajectory) {
  const std::string& folder = sequenceFolder();
  SlamOptions options;
  options.progress = false;
  options.tracker.asynchronous_backend = false;
  options.build_map = false;
  options.write_masks = true;
  options.filter.geometric = false;  // only the detector finds people: none before frame 30
  const auto runWith = [&](int backfill_frames, const std::string& name) {
    options.backfill.frames = backfill_frames;
    const std::string run = testing::TempDir() + name;
    SlamSystem system(options, std::make_unique<LateDetector>(folder, 30));
    const TumSequence sequence(folder);
    RecordedStream stream(sequence, 0, 2, nullptr);
    SlamRunner::Options runner;
    runner.progress = false;
    runToFolder(&system, &stream, run, runner);
    return run;
  };
  const std::string without = runWith(0, "pf2_pipeline_no_backfill");
  const std::string with = runWith(30, "pf2_pipeline_backfill");
  const auto [removed_without, all] = personPixelsRemoved(folder, without, 20, 30);
  const auto [removed_with, all_with] = personPixelsRemoved(folder, with, 20, 30);
  std::printf("people's depth removed in frames 20-29: %ld / %ld without, %ld with\n", removed_without, all,
              removed_with);
  ASSERT_GT(all, 1000);
  EXPECT_EQ(removed_without, 0);  // nobody found, nothing to carry
  EXPECT_GT(removed_with, all / 4);
  // It only adds: every pixel removed without it is removed with it.
  const TumSequence sequence(folder);
  for (size_t i = 0; i < sequence.size(); ++i) {
    char name[64];
    std::snprintf(name, sizeof(name), "/masks/%.6f.png", sequence.frame(i).timestamp);
    const cv::Mat a = cv::imread(without + name, cv::IMREAD_UNCHANGED), b = cv::imread(with + name, cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(a.empty() || b.empty()) << name;
    EXPECT_EQ(cv::countNonZero(a & ~b), 0) << name;
  }
  // The tracker never waited for it.
  const Trajectory a = readTrajectory(without + "/trajectory.txt"), b = readTrajectory(with + "/trajectory.txt");
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].T_w_c.matrix(), b[i].T_w_c.matrix()) << i;
  }
}

}  // namespace
}  // namespace pf2
