// pf2_slam's humans.txt on a small generated sequence (half resolution, 90 frames, xyz camera,
// 3 people), scored against the sequence's ground-truth pelvis positions.
#include <fstream>
#include <set>
#include <sstream>

#include <gtest/gtest.h>

#include "pf2/core/config_file.h"
#include "pf2/core/error.h"
#include "pf2/core/text_lines.h"
#include "pf2/eval/human_metrics.h"
#include "pf2/humans/human_track.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/io/tum_sequence.h"
#include "pf2/slam/slam_system.h"
#include "pf2/synth/synthetic_sequence.h"

namespace pf2 {
namespace {

const std::string& sequenceFolder() {
  static const std::string folder = [] {
    SyntheticSequence::Options options;
    options.frames = 90;
    options.people = 3;
    options.intrinsics = CameraIntrinsics::tumFreiburg3().scaled(0.5);
    const std::string out = testing::TempDir() + "pf2_humans_sequence";
    SyntheticSequence(options).writeTumFolder(out);
    return out;
  }();
  return folder;
}

// The run's people, scored against the ground truth of the people in view (gt/boxes.txt), after
// moving the run's world (first camera) into the room frame.
HumanMetrics score(const std::string& run) {
  const std::string& folder = sequenceFolder();
  const Trajectory estimate = readTrajectory(run + "/trajectory.txt");
  const Trajectory truth = readTrajectory(folder + "/groundtruth.txt");
  EXPECT_EQ(estimate.size(), truth.size());
  const Eigen::Isometry3d T_gt_est = truth.front().T_w_c * estimate.front().T_w_c.inverse();
  std::vector<HumanTrack> tracks = readHumanTracks(run + "/humans.txt");
  for (HumanTrack& track : tracks) {
    for (HumanTrackPoint& point : track.points) point.p_w = T_gt_est * point.p_w;
  }
  std::set<std::pair<double, int>> in_view;
  forEachDataLine(folder + "/gt/boxes.txt", "boxes", [&](const std::string& line, int) {
    std::istringstream fields(line);
    double stamp = 0;
    int id = 0;
    fields >> stamp >> id;
    in_view.insert({stamp, id});
  });
  std::vector<HumanTrack> people = readHumanTracks(folder + "/gt/people.txt");
  for (HumanTrack& person : people) {
    std::vector<HumanTrackPoint> kept;
    for (const HumanTrackPoint& point : person.points) {
      if (in_view.count({point.timestamp, person.id})) kept.push_back(point);
    }
    person.points = kept;
  }
  return evaluateHumanTracks(people, tracks);
}

SlamOptions fastOptions() {
  SlamOptions options;
  options.detector = "gt";
  options.progress = false;
  options.build_map = false;
  options.tracker.asynchronous_backend = false;
  return options;
}

TEST(SlamHumans, TrajectoriesOfThePeopleInView) {
  const std::string run = testing::TempDir() + "pf2_humans_run";
  SlamSystem system(fastOptions());
  system.run(TumSequence(sequenceFolder()), sequenceFolder(), run);
  const HumanMetrics m = score(run);
  // Measured: 250 of 252 person-frames, 3 tracks, no switch, median 0.21 m (0.11 m once each
  // person's constant offset between centre and pelvis is taken off).
  ASSERT_GT(m.frames, 150);
  EXPECT_GT(m.recall, 0.95);
  EXPECT_EQ(m.id_switches, 0);
  EXPECT_EQ(m.tracks, 3);
  EXPECT_LT(m.error.median, 0.3);
  EXPECT_LT(m.error_without_offset.median, 0.15);
  // The run's stats carry the stage.
  EXPECT_EQ(system.stats().summary("humans").count, 90);
}

TEST(SlamHumans, ConfigKeysAndNoFileWithoutDetector) {
  ConfigFile config;
  SlamOptions options = fastOptions();
  const std::string path = testing::TempDir() + "pf2_humans.cfg";
  {
    std::ofstream out(path);
    out << "humans.association paper\nhumans.gate 0.7\nhumans.max_missed 5\nhumans.depth_in_interval false\n";
  }
  applyConfig(ConfigFile::load(path), &options);
  EXPECT_EQ(options.humans.association, HumanTracker::Association::kPaper);
  EXPECT_DOUBLE_EQ(options.humans.gate, 0.7);
  EXPECT_EQ(options.humans.max_missed, 5);
  EXPECT_FALSE(options.human_depth_in_interval);
  {
    std::ofstream out(path);
    out << "humans.association nearest\n";
  }
  EXPECT_THROW(applyConfig(ConfigFile::load(path), &options), Error);
  // Without a detector there are no people and no humans.txt.
  options = fastOptions();
  options.detector = "none";
  SyntheticSequence::Options three_frames;
  three_frames.frames = 3;
  three_frames.intrinsics = CameraIntrinsics::tumFreiburg3().scaled(0.5);
  const std::string run = testing::TempDir() + "pf2_humans_none";
  SlamSystem(options).run(SyntheticSequence(three_frames), "", run);
  EXPECT_FALSE(std::ifstream(run + "/humans.txt").good());
}

}  // namespace
}  // namespace pf2
