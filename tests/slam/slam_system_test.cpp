#include "pf2/slam/slam_system.h"

#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/eval/trajectory_metrics.h"
#include "pf2/io/trajectory_io.h"
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

TEST(SlamSystem, BlindFramesAreLostNotInvented) {
  const SyntheticSequence sequence(smallSequence(0, 40));
  const BlankedSource source(sequence, 15, 20);
  SlamOptions options;
  options.detector = "none";
  options.progress = false;
  options.build_map = false;
  options.tracker.asynchronous_backend = false;
  options.tracker.max_bridged_frames = 2;
  SlamSystem system(options);
  const std::string out = testing::TempDir() + "pf2_slam_blind";
  const SlamRunSummary summary = system.run(source, "", out);
  // Frames 15 and 16 are bridged (prior pose), 17-19 lost, 20 relocalised.
  EXPECT_EQ(summary.bridged, 2);
  EXPECT_EQ(summary.lost, 3);
  EXPECT_EQ(summary.relocalised, 1);
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

class EmptySource : public FrameSource {
 public:
  size_t size() const override { return 0; }
  Frame frame(size_t) const override { throw Error("no frames"); }
  std::string description() const override { return "empty"; }
};

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
