#include "pf2/slam/slam_system.h"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/eval/trajectory_metrics.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/io/tum_sequence.h"
#include "pf2/registration/rgbd_odometry.h"
#include "pf2/synth/synthetic_sequence.h"

namespace pf2 {
namespace {

// A half-resolution synthetic sequence keeps the test fast; frames in [blank_from, blank_to)
// are replaced by a sensor that sees nothing (lens covered), which tracking must report as lost.
class BlankedSource : public FrameSource {
 public:
  BlankedSource(const SyntheticSequence& sequence, int blank_from, int blank_to)
      : sequence_(sequence), blank_from_(blank_from), blank_to_(blank_to) {}
  size_t size() const override { return sequence_.size(); }
  std::string description() const override { return "blanked " + sequence_.description(); }
  Frame frame(size_t i) const override {
    Frame frame = sequence_.frame(i);
    if (static_cast<int>(i) >= blank_from_ && static_cast<int>(i) < blank_to_) {
      frame.depth.setTo(0.0f);
      frame.rgb.setTo(cv::Scalar::all(0));
    }
    return frame;
  }

 private:
  const SyntheticSequence& sequence_;
  int blank_from_, blank_to_;
};

// A sequence built to make the odometry fail: every 7th frame is random depth and colour, frames
// 20-24 are taken from 30 frames later (a jump the camera cannot make), frames 40-44 see one grey
// plane at 1 m (no texture, a single surface: the pose is unconstrained).
class HostileSource : public FrameSource {
 public:
  explicit HostileSource(const SyntheticSequence& sequence) : sequence_(sequence) {}
  size_t size() const override { return sequence_.size(); }
  std::string description() const override { return "hostile " + sequence_.description(); }
  Frame frame(size_t i) const override {
    const bool jumped = i >= 20 && i < 25 && i + 30 < sequence_.size();
    Frame frame = sequence_.frame(jumped ? i + 30 : i);
    frame.timestamp = sequence_.timestamp(i);
    frame.index = static_cast<int>(i);
    if (i % 7 == 3) {
      cv::RNG rng(static_cast<uint64_t>(i));
      rng.fill(frame.depth, cv::RNG::UNIFORM, 0.3, 6.0);
      rng.fill(frame.rgb, cv::RNG::UNIFORM, 0, 255);
    } else if (i >= 40 && i < 45) {
      frame.depth.setTo(1.0f);
      frame.rgb.setTo(cv::Scalar::all(128));
    }
    return frame;
  }

 private:
  const SyntheticSequence& sequence_;
};

SyntheticSequence::Options smallSequence(int people, int frames) {
  SyntheticSequence::Options options;
  options.frames = frames;
  options.people = people;
  options.intrinsics = CameraIntrinsics::tumFreiburg3().scaled(0.5);
  return options;
}

Trajectory groundTruth(const SyntheticSequence& sequence) {
  Trajectory trajectory;
  for (size_t i = 0; i < sequence.size(); ++i) trajectory.push_back({sequence.timestamp(i), sequence.pose(i)});
  return trajectory;
}

// Camera tracking alone (no detector, no map), the back end in the tracker's thread: repeatable.
SlamOptions repeatableTrackingOnly() {
  SlamOptions options;
  options.detector = "none";
  options.progress = false;
  options.build_map = false;
  options.tracker.asynchronous_backend = false;
  return options;
}

std::string readAll(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(SlamSystem, TracksAStaticRoomToAFewMillimetres) {
  const SyntheticSequence sequence(smallSequence(0, 45));
  SlamOptions options;
  options.detector = "none";
  options.progress = false;
  options.tracker.asynchronous_backend = false;
  const std::string out = testing::TempDir() + "pf2_slam_static";
  SlamSystem system(options);
  const SlamRunSummary summary = system.run(sequence, "", out);
  EXPECT_EQ(summary.frames, 45);
  EXPECT_EQ(summary.lost, 0);
  EXPECT_GE(summary.keyframes, 1);
  // The written trajectory is the one returned, and it is accurate.
  const Trajectory written = readTrajectory(out + "/trajectory.txt");
  ASSERT_EQ(written.size(), 45u);
  const AteResult ate = computeAte(groundTruth(sequence), written);
  EXPECT_LT(ate.translation.rmse, 0.01);
  // stats.json carries the run's figures.
  const std::string stats = readAll(out + "/stats.json");
  EXPECT_NE(stats.find("\"frames\":45"), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"lost\":0"), std::string::npos) << stats;
  EXPECT_NE(stats.find("\"track\":{\"count\":45"), std::string::npos) << stats;
  // The map was fused and written.
  EXPECT_GT(readAll(out + "/map.ply").size(), 1000u);
}

// The world's up from the room's floor and table (full resolution: at half size this room's
// floor gives too few normals per frame). The run's world is the first camera's frame,
// pf2_synth's room has z up, and its camera looks down, so the first camera's -y is off.
TEST(SlamSystem, FindsTheWorldsUpFromTheFloor) {
  SyntheticSequence::Options sequence_options = smallSequence(0, 20);
  sequence_options.intrinsics = CameraIntrinsics::tumFreiburg3();
  const SyntheticSequence sequence(sequence_options);
  const std::string out = testing::TempDir() + "pf2_slam_up";
  SlamSystem system(repeatableTrackingOnly());
  const SlamRunSummary summary = system.run(sequence, "", out);
  const Eigen::Vector3d truth = sequence.pose(0).linear().transpose() * Eigen::Vector3d::UnitZ();
  const auto degrees = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 / M_PI;
  };
  EXPECT_TRUE(summary.up_estimated);
  EXPECT_LT(degrees(summary.up_w, truth), 2.0);
  EXPECT_GT(degrees(Eigen::Vector3d(0, -1, 0), truth), 5.0);
  RecordProperty("up_error_deg", std::to_string(degrees(summary.up_w, truth)));
  EXPECT_NE(readAll(out + "/stats.json").find("\"world_up_estimated\":true"), std::string::npos);
}

// Real frames of fast rotation (TUM fr1/rpy, 3-4 degrees per frame, blur, rolling shutter; no
// person): the camera tracked with the photometric term's Huber threshold at its default and at the
// point-to-plane term's 1.345. The wider threshold was chosen on the real sequences (this one and
// the Bonn crowd frames); pf2_synth's Gaussian noise favours the narrower one.
double tumRpyAte(const std::string& folder, double photometric_huber_k) {
  const TumSequence sequence(folder);
  SlamOptions options = repeatableTrackingOnly();
  options.tracker.odometry.distortion = kTumFreiburg1Distortion;
  options.tracker.odometry.photometric_huber_k = photometric_huber_k;
  const std::string out = testing::TempDir() + "pf2_slam_tum_rpy";
  SlamSystem system(options);
  system.run(sequence, folder, out);
  return computeAte(sequence.groundTruth(), readTrajectory(out + "/trajectory.txt")).translation.rmse;
}

TEST(SlamSystem, RealTumRpyTracksBetterWithTheWiderPhotometricThreshold) {
  const std::string folder = std::string(PF2_SHARED_DATA) + "/tum_fr1_rpy_120";
  struct stat info;
  if (::stat((folder + "/rgb.txt").c_str(), &info) != 0) GTEST_SKIP() << "no " << folder;
  const double wide = tumRpyAte(folder, RgbdOdometry::Options().photometric_huber_k);
  const double narrow = tumRpyAte(folder, 1.345);
  std::printf("fr1_rpy_120 ATE: %.2f mm (photometric Huber default), %.2f mm (1.345)\n", 1000 * wide, 1000 * narrow);
  EXPECT_LT(wide, narrow);
  EXPECT_LT(wide, 0.011);
}

// 40 frames, 15-19 without depth or colour; two frames may be bridged before the camera is lost.
SlamOptions blindFramesOptions() {
  SlamOptions options;
  options.detector = "none";
  options.progress = false;
  options.build_map = false;
  options.tracker.asynchronous_backend = false;
  options.tracker.max_bridged_frames = 2;
  return options;
}

void expectFrameCounts(const SlamRunSummary& summary, int bridged, int lost, int relocalised) {
  EXPECT_EQ(summary.bridged, bridged);
  EXPECT_EQ(summary.lost, lost);
  EXPECT_EQ(summary.relocalised, relocalised);
}

TEST(SlamSystem, BlindFramesAreLostNotInvented) {
  const SyntheticSequence sequence(smallSequence(0, 40));
  const BlankedSource source(sequence, 15, 20);
  SlamOptions options = blindFramesOptions();
  options.gaps.max_gap = 0;  // as tracking left them (the next test fills them)
  SlamSystem system(options);
  const std::string out = testing::TempDir() + "pf2_slam_blind";
  const SlamRunSummary summary = system.run(source, "", out);
  // Frames 15 and 16 are bridged (prior pose), 17-19 lost, 20 relocalised.
  expectFrameCounts(summary, 2, 3, 1);
  EXPECT_EQ(summary.interpolated, 0);
  ASSERT_EQ(system.trajectory().size(), 37u);
  for (const StampedPose& pose : system.trajectory()) {
    for (int i = 17; i < 20; ++i) EXPECT_NE(pose.timestamp, sequence.timestamp(i));
  }
  // stats.json marks every frame.
  const std::string stats = readAll(out + "/stats.json");
  EXPECT_NE(stats.find("\"bridged\":2"), std::string::npos) << stats;
  size_t bridged_entries = 0, lost_entries = 0;
  for (size_t at = 0; (at = stats.find("\"status\":\"bridged\"", at)) != std::string::npos; ++at) ++bridged_entries;
  for (size_t at = 0; (at = stats.find("\"status\":\"lost\"", at)) != std::string::npos; ++at) ++lost_entries;
  EXPECT_EQ(bridged_entries, 2u);
  EXPECT_EQ(lost_entries, 3u);
  // After relocalisation the poses are right again.
  EXPECT_LT(computeAte(groundTruth(sequence), system.trajectory()).translation.rmse, 0.01);
}

TEST(SlamSystem, BlindFramesBetweenMeasuredOnesGetInterpolatedPoses) {
  const SyntheticSequence sequence(smallSequence(0, 40));
  const BlankedSource source(sequence, 15, 20);
  SlamSystem system(blindFramesOptions());
  const std::string out = testing::TempDir() + "pf2_slam_blind_filled";
  const SlamRunSummary summary = system.run(source, "", out);
  // Frames 15-19 lie between measured frames 14 and 20 (relocalised): all five are bridged now.
  expectFrameCounts(summary, 5, 0, 1);
  EXPECT_EQ(summary.interpolated, 5);  // the two the prior had bridged and the three lost
  ASSERT_EQ(system.trajectory().size(), 40u);
  const std::string stats = readAll(out + "/stats.json");
  EXPECT_NE(stats.find("\"bridged\":5,\"interpolated\":5,"), std::string::npos) << stats;
  EXPECT_EQ(stats.find("\"status\":\"lost\""), std::string::npos) << stats;
  const Trajectory truth = groundTruth(sequence);
  const AteResult ate = computeAte(truth, system.trajectory());
  std::printf("blind frames filled: ATE rmse %.2f mm, max %.2f mm\n", 1000 * ate.translation.rmse,
              1000 * ate.translation.max);
  EXPECT_LT(ate.translation.rmse, 0.01);
  EXPECT_LT(ate.translation.max, 0.01);
}

// Whatever the frames, no written pose is more than a short hop from its neighbours: rejected
// odometry never reaches the trajectory, bridged frames follow the damped prior. Three people walk
// through the view and are not removed (no detector), so the odometry is pulled by them as well.
// Measured: largest step 5.5 cm with the divergence guard, 13 cm without it (all guard limits set
// to 1e9, no bridging); the camera moves about 1 cm per frame.
TEST(SlamSystem, NoPoseJumpsOnASequenceBuiltToBreakTheOdometry) {
  const SyntheticSequence sequence(smallSequence(3, 60));
  const HostileSource source(sequence);
  SlamSystem system(repeatableTrackingOnly());
  const SlamRunSummary summary = system.run(source, "", testing::TempDir() + "pf2_slam_hostile");
  EXPECT_GT(summary.bridged + summary.lost, 8);  // the random frames at least
  const Trajectory& poses = system.trajectory();
  ASSERT_GT(poses.size(), 40u);
  double largest_step = 0.0;
  for (size_t i = 0; i < poses.size(); ++i) {
    ASSERT_TRUE(poses[i].T_w_c.matrix().allFinite()) << "pose " << i;
    if (i > 0) {
      largest_step = std::max(largest_step, (poses[i].T_w_c.translation() - poses[i - 1].T_w_c.translation()).norm());
    }
  }
  EXPECT_LT(largest_step, 0.09);
  // People left in the depth pull the camera off (tens of centimetres), never away.
  EXPECT_LT(computeAte(groundTruth(sequence), poses).translation.max, 1.0);
}

// Settings outside their declared range are refused before any work, naming the setting.
TEST(SlamSystem, SettingsOutOfRangeAreNamed) {
  const auto expectRefused = [](SlamOptions options, const std::string& key) {
    try {
      SlamSystem system(options);
      FAIL() << key << " accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("range"), std::string::npos) << e.what();
    }
  };
  SlamOptions options;
  options.filter.mask_box_reach = -5;
  expectRefused(options, "filter.mask_reach");
  options = SlamOptions();
  options.tracker.max_bridged_frames = -1;
  expectRefused(options, "tracker.max_bridged_frames");
  options = SlamOptions();
  options.tracker.odometry.min_intensity_sigma = 0.5;  // above intensity_sigma
  expectRefused(options, "tracker.min_intensity_sigma");
  options = SlamOptions();
  options.geometric_margin = 0.0;
  expectRefused(options, "filter.geometric_margin");
  EXPECT_NO_THROW(SlamSystem{SlamOptions()});
}

class EmptySource : public FrameSource {
 public:
  size_t size() const override { return 0; }
  Frame frame(size_t) const override { throw Error("no frames"); }
  std::string description() const override { return "empty"; }
};

// The library without files: frames fed one at a time (as from a live camera), each result
// returned, the final result (trajectory, map) in memory; the writer saves it only when asked.
TEST(SlamSystem, ProcessesFramesOneAtATimeAndReturnsTheResult) {
  const SyntheticSequence sequence(smallSequence(0, 30));
  SlamOptions options;
  options.progress = false;
  options.tracker.asynchronous_backend = false;
  SlamSystem system(options, nullptr);
  for (size_t i = 0; i < sequence.size(); ++i) {
    const Frame frame = sequence.frame(i);
    const FrameResult r = system.process(frame);
    EXPECT_EQ(r.timestamp, frame.timestamp);
    EXPECT_TRUE(r.has_pose) << i;
    EXPECT_EQ(cv::countNonZero(r.static_depth != frame.depth), 0);  // no detector: nothing removed
    EXPECT_TRUE(r.removed.empty());
    EXPECT_TRUE(r.people.empty());
  }
  const SlamResult result = system.finish();
  EXPECT_EQ(result.summary.frames, 30);
  EXPECT_EQ(result.summary.detector, "none");
  ASSERT_EQ(result.trajectory.size(), 30u);
  EXPECT_LT(computeAte(groundTruth(sequence), result.trajectory).translation.rmse, 0.01);
  ASSERT_TRUE(result.map);
  EXPECT_GT(result.map->extractMesh().vertices.size(), 1000u);
  EXPECT_EQ(result.frame_status.size(), 30u);
  EXPECT_THROW(system.process(sequence.frame(0)), Error);  // finished

  const std::string out = testing::TempDir() + "pf2_slam_written";
  std::remove((out + "/trajectory.txt").c_str());
  ::mkdir(out.c_str(), 0755);
  writeSlamResult(out, result, &system.stats());
  EXPECT_EQ(readTrajectory(out + "/trajectory.txt").size(), 30u);
  EXPECT_NE(readAll(out + "/stats.json").find("\"map_export\""), std::string::npos);
  EXPECT_GT(readAll(out + "/map.ply").size(), 1000u);
}

// 60 frames of a camera on a half sphere, without people.
SyntheticSequence::Options halfsphereSequence() {
  SyntheticSequence::Options motion = smallSequence(0, 60);
  motion.camera = CameraMotion::kHalfsphere;
  return motion;
}

// No detector; the back end and the mapper in the caller's thread, so runs repeat; no OctoMap.
SlamOptions repeatableMapOptions() {
  SlamOptions options;
  options.detector = "none";
  options.progress = false;
  options.tracker.asynchronous_backend = false;
  options.synchronous_map = true;
  options.mapper.build_occupancy = false;
  return options;
}

// With the back end and the mapper in the caller's thread, a run is reproducible to the byte:
// the same trajectory and the same map on every run. (With the mapper in its own thread, pf2_slam
// on 60 full-resolution halfsphere frames gave three different maps in three runs: the pose
// graph's corrections reach the mapper at different moments. That race is not reproduced here;
// this guards the synchronous path against any other source of run-to-run difference.)
TEST(SlamSystem, SynchronousRunsGiveTheSameMapEveryTime) {
  const SyntheticSequence sequence(halfsphereSequence());
  SlamOptions options = repeatableMapOptions();
  std::string maps[2], trajectories[2];
  for (int run = 0; run < 2; ++run) {
    const std::string out = testing::TempDir() + "pf2_slam_repeat_" + std::to_string(run);
    SlamSystem(options).run(sequence, "", out);
    maps[run] = readAll(out + "/map.ply");
    trajectories[run] = readAll(out + "/trajectory.txt");
  }
  EXPECT_GT(maps[0].size(), 1000u);
  EXPECT_TRUE(maps[0] == maps[1]);
  EXPECT_TRUE(trajectories[0] == trajectories[1]);
}

// The pose graph's corrections reach the map once at the end (the default) or after every
// correction (map.follow_corrections): the same final map, from fewer re-fusions.
TEST(SlamSystem, CorrectionsReachTheMapAtTheEndAsAfterEveryCorrection) {
  const SyntheticSequence sequence(halfsphereSequence());
  SlamOptions options = repeatableMapOptions();
  std::shared_ptr<Mapper> maps[2];
  for (const bool follow : {true, false}) {
    options.follow_corrections = follow;
    SlamSystem system(options, nullptr);
    for (size_t i = 0; i < sequence.size(); ++i) system.process(sequence.frame(i));
    maps[follow ? 0 : 1] = system.finish().map;
  }
  ASSERT_TRUE(maps[0] && maps[1]);
  EXPECT_GT(maps[1]->refusions(), 0);  // the back end did move keyframes
  EXPECT_GE(maps[0]->refusions(), maps[1]->refusions());
  const TsdfVolume::BlockMap& followed = maps[0]->tsdf().blocks();
  const TsdfVolume::BlockMap& at_end = maps[1]->tsdf().blocks();
  EXPECT_EQ(followed.size(), at_end.size());
  double sum = 0.0;  // of |tsdf difference|, tsdf in units of the truncation (4 cm)
  int compared = 0, apart = 0;
  for (const auto& [index, block] : followed) {
    const auto other = at_end.find(index);
    ASSERT_NE(other, at_end.end());
    for (int i = 0; i < TsdfVolume::kBlockVoxels; ++i) {
      if (block->voxels[i].weight <= 0.f) continue;
      const float difference = std::abs(block->voxels[i].tsdf - other->second->voxels[i].tsdf);
      sum += difference;
      apart += difference > 0.05f;
      ++compared;
    }
  }
  // Within the Mapper's own tolerance (frames moved by under 1 mm / 1 mrad are left where they
  // were fused): under 0.5 % of the truncation on average (0.1 % here) and 1 % of the voxels 2 mm
  // apart (0.4 %).
  ASSERT_GT(compared, 100000);
  EXPECT_LT(sum / compared, 0.005);
  EXPECT_LT(apart, compared / 100);
}

TEST(SlamSystem, EmptySourceAndBadOutputAreErrors) {
  SlamOptions options;
  options.progress = false;
  options.detector = "none";
  SlamSystem system(options);
  try {
    system.run(EmptySource(), "", testing::TempDir() + "pf2_slam_empty");
    FAIL() << "an empty sequence was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no frames"), std::string::npos) << e.what();
  }
  try {
    system.run(EmptySource(), "", "/nonexistent-pf2-folder/a/b");
    FAIL() << "an unwritable output folder was accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-pf2-folder/a/b"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace pf2
