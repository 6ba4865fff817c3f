// The whole pipeline as pf2_slam runs it, with people and the map on: detector (the ground-truth
// oracle, which needs no model files) -> Dual-BBox filter with its additions -> tracker -> human
// tracks -> TSDF map, on a small generated sequence (half resolution, 60 frames, xyz camera, three
// people). The same run without person removal shows what removal buys in the map.
#include <set>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

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

// The ground truth's people with their masks, each with 17 keypoints on their mask (as a pose
// network gives them), found only from frame `first` on (a detector that finds everyone late), the
// masks grown by `spill` pixels onto what is around them (as a segmenter's blurred outline does).
class AlteredGtDetector : public HumanDetector {
 public:
  AlteredGtDetector(const std::string& folder, int first, int spill)
      : gt_(gtOptions(folder)), first_(first), spill_(spill) {}
  std::string name() const override { return "altered gt"; }
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
      if (spill_ > 0) {
        const int size = 2 * spill_ + 1;
        cv::dilate(person.mask, person.mask, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size, size)));
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
  int spill_;
  int frame_ = 0;
};

// Pixels with depth removed in the masks of frames [from, to), of the people (ground truth) and of
// the rest, and how many of each there are.
struct RemovedPixels {
  long person_removed = 0, person = 0, static_removed = 0, static_pixels = 0;
};
RemovedPixels pixelsRemoved(const std::string& folder, const std::string& run, int from, int to) {
  const TumSequence sequence(folder);
  RemovedPixels r;
  for (int i = from; i < to; ++i) {
    const Frame frame = sequence.frame(i);
    char name[64];
    std::snprintf(name, sizeof(name), "%.6f.png", frame.timestamp);
    const cv::Mat person = cv::imread(folder + "/gt/masks/" + name, cv::IMREAD_UNCHANGED) > 0;
    const cv::Mat mask = cv::imread(run + "/masks/" + name, cv::IMREAD_UNCHANGED) > 0;
    const cv::Mat measured = frame.depth > 0.f;
    r.person += cv::countNonZero(measured & person);
    r.person_removed += cv::countNonZero(measured & person & mask);
    r.static_pixels += cv::countNonZero(measured & ~person);
    r.static_removed += cv::countNonZero(measured & ~person & mask);
  }
  return r;
}

// pf2_slam's pipeline without the map, writing masks, repeatable (the back end in the frame's thread).
SlamOptions maskRunOptions() {
  SlamOptions options;
  options.progress = false;
  options.tracker.asynchronous_backend = false;
  options.build_map = false;
  options.write_masks = true;
  return options;
}

// A run of pf2_slam's pipeline with `options` and `detector`; its folder.
std::string runWithMasks(const SlamOptions& options, std::unique_ptr<HumanDetector> detector, const std::string& name) {
  const std::string& folder = sequenceFolder();
  const std::string run = testing::TempDir() + name;
  SlamSystem system(options, std::move(detector));
  const TumSequence sequence(folder);
  RecordedStream stream(sequence, 0, 2, nullptr);
  SlamRunner::Options runner;
  runner.progress = false;
  runToFolder(&system, &stream, run, runner);
  return run;
}

void expectSameTrajectory(const std::string& run_a, const std::string& run_b) {
  const Trajectory a = readTrajectory(run_a + "/trajectory.txt"), b = readTrajectory(run_b + "/trajectory.txt");
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].T_w_c.matrix(), b[i].T_w_c.matrix()) << i;
  }
}

TEST(SlamPipeline, PeopleFoundLateLeaveTheMapsFramesBeforeButNotTheTrajectory) {
  const std::string& folder = sequenceFolder();
  SlamOptions options = maskRunOptions();
  options.filter.geometric = false;  // only the detector finds people: none before frame 30
  options.backfill.give_back_views = 0;  // carrying alone (giving back and taking: the next tests)
  options.backfill.seen_through_views = 0;
  const auto runWith = [&](int backfill_frames, const std::string& name) {
    options.backfill.frames = backfill_frames;
    return runWithMasks(options, std::make_unique<AlteredGtDetector>(folder, 30, 0), name);
  };
  const std::string without = runWith(0, "pf2_pipeline_no_backfill");
  const std::string with = runWith(30, "pf2_pipeline_backfill");
  const RemovedPixels a = pixelsRemoved(folder, without, 20, 30), b = pixelsRemoved(folder, with, 20, 30);
  std::printf("people's depth removed in frames 20-29: %ld / %ld without, %ld with\n", a.person_removed, a.person,
              b.person_removed);
  ASSERT_GT(a.person, 1000);
  EXPECT_EQ(a.person_removed, 0);  // nobody found, nothing to carry
  EXPECT_GT(b.person_removed, a.person / 4);
  // It only adds: every pixel removed without it is removed with it.
  const TumSequence sequence(folder);
  for (size_t i = 0; i < sequence.size(); ++i) {
    char name[64];
    std::snprintf(name, sizeof(name), "/masks/%.6f.png", sequence.frame(i).timestamp);
    const cv::Mat a = cv::imread(without + name, cv::IMREAD_UNCHANGED), b = cv::imread(with + name, cv::IMREAD_UNCHANGED);
    ASSERT_FALSE(a.empty() || b.empty()) << name;
    EXPECT_EQ(cv::countNonZero(a & ~b), 0) << name;
  }
  expectSameTrajectory(without, with);  // the tracker never waited for it
}

TEST(SlamPipeline, WhatASpilledMaskTookBesideThePeopleIsGivenBackToTheMapButNotThePeople) {
  const std::string& folder = sequenceFolder();
  SlamOptions options = maskRunOptions();
  options.behind_body_margin = 0.0;  // this rule alone (the spill behind the people: the next test)
  const auto runWith = [&](int give_back_views, const std::string& name) {
    options.backfill.give_back_views = give_back_views;
    return runWithMasks(options, std::make_unique<AlteredGtDetector>(folder, 0, 6), name);
  };
  const std::string without = runWith(0, "pf2_pipeline_no_give_back");
  const std::string with = runWith(3, "pf2_pipeline_give_back");
  // Frames 0-29 waited their 30 frames (the later ones fewer: the run's end).
  const RemovedPixels a = pixelsRemoved(folder, without, 0, 30), b = pixelsRemoved(folder, with, 0, 30);
  std::printf("static depth removed: %ld without, %ld with (of %ld); people's: %ld, %ld (of %ld)\n",
              a.static_removed, b.static_removed, a.static_pixels, a.person_removed, b.person_removed, a.person);
  ASSERT_GT(a.static_removed, 10000);
  // Most of what the spill takes here lies around a person seated all along, whose spill the later
  // frames remove too (it stays); what lay beside the people who walked on comes back: 7 % of it.
  EXPECT_LT(b.static_removed, 0.95 * a.static_removed);
  EXPECT_GE(b.person_removed, 0.99 * a.person_removed);
  expectSameTrajectory(without, with);
}

TEST(SlamPipeline, WhatASpilledMaskTookBehindThePeopleGoesToTheMapButNotThePeople) {
  const std::string& folder = sequenceFolder();
  SlamOptions options = maskRunOptions();
  options.backfill.give_back_views = 0;  // this rule alone
  options.backfill.seen_through_views = 0;
  const auto runWith = [&](double behind_body_margin, const std::string& name) {
    options.behind_body_margin = behind_body_margin;
    return runWithMasks(options, std::make_unique<AlteredGtDetector>(folder, 0, 6), name);
  };
  const std::string without = runWith(0.0, "pf2_pipeline_nothing_behind");
  const std::string with = runWith(0.5, "pf2_pipeline_behind");
  const TumSequence sequence(folder);
  const RemovedPixels a = pixelsRemoved(folder, without, 0, static_cast<int>(sequence.size()));
  const RemovedPixels b = pixelsRemoved(folder, with, 0, static_cast<int>(sequence.size()));
  std::printf("static depth removed: %ld without, %ld with (of %ld); people's: %ld, %ld (of %ld)\n",
              a.static_removed, b.static_removed, a.static_pixels, a.person_removed, b.person_removed, a.person);
  ASSERT_GT(a.static_removed, 10000);
  // Part of the 6 px spill lies on the wall and the floor well behind the people, the rest on the
  // chairs, the desk and the floor at their depth: a third of it comes back (36 % when written).
  EXPECT_LT(b.static_removed, 0.8 * a.static_removed);
  EXPECT_GE(b.person_removed, 0.995 * a.person_removed);
  expectSameTrajectory(without, with);  // the tracker has the filter's depth
}

TEST(SlamPipeline, PeopleNobodyFoundAreTakenFromTheMapWhereTheFramesAroundSawThroughThem) {
  const std::string& folder = sequenceFolder();
  SlamOptions options = maskRunOptions();
  // The detector finds nobody: only the filter's geometric addition (against the keyframes'
  // prediction) removes people, and keeps the tracker on the room.
  const auto runWith = [&](int seen_through_views, const std::string& name) {
    options.backfill.seen_through_views = seen_through_views;
    return runWithMasks(options, std::make_unique<AlteredGtDetector>(folder, 1000, 0), name);
  };
  const std::string without = runWith(0, "pf2_pipeline_no_seen_through");
  const std::string with = runWith(1, "pf2_pipeline_seen_through");
  const RemovedPixels a = pixelsRemoved(folder, without, 0, 30), b = pixelsRemoved(folder, with, 0, 30);
  std::printf("people's depth removed: %ld without, %ld with (of %ld); static depth: %ld, %ld (of %ld)\n",
              a.person_removed, b.person_removed, a.person, a.static_removed, b.static_removed, a.static_pixels);
  ASSERT_GT(a.person, 10000);
  // Of the people who walk (one sits all along, and nothing sees through him) the frames around saw
  // the room behind where they stood: a tenth of all the people's depth more removed (16 % -> 31 %
  // when written; at 320 x 240 the 15 px kept free of nearer depth around a pixel are twice as wide
  // as at full size).
  EXPECT_GT(b.person_removed, a.person_removed + a.person / 10);
  EXPECT_LT(b.static_removed - a.static_removed, 0.001 * a.static_pixels);
  expectSameTrajectory(without, with);
}

}  // namespace
}  // namespace pf2
