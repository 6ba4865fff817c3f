// The frame loop: a live stream (a recording delivered on a clock, the live path without a
// camera) through the pipeline with detection running ahead; frames the pipeline cannot take are
// dropped and counted, never queued up; a stop request ends the run with a complete result folder.
#include <atomic>
#include <filesystem>

#include <gtest/gtest.h>

#include "pf2/io/frame_streams.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/slam/slam_runner.h"
#include "pf2/synth/synthetic_sequence.h"

namespace pf2 {
namespace {

const SyntheticSequence& sequence() {
  static const SyntheticSequence made = [] {
    SyntheticSequence::Options options;
    options.frames = 45;
    options.people = 2;
    options.intrinsics = CameraIntrinsics::tumFreiburg3().scaled(0.5);
    return SyntheticSequence(options);
  }();
  return made;
}

// The sequence's frames rendered once and held in memory, so that delivering one costs nothing.
class MemorySource : public FrameSource {
 public:
  explicit MemorySource(const FrameSource& source) {
    for (size_t i = 0; i < source.size(); ++i) frames_.push_back(source.frame(i));
  }
  size_t size() const override { return frames_.size(); }
  Frame frame(size_t i) const override { return frames_.at(i); }
  std::string description() const override { return "in memory"; }

 private:
  std::vector<Frame> frames_;
};

SlamOptions quietOptions() {
  SlamOptions options;
  options.progress = false;
  options.build_map = false;
  return options;
}

// Delivered 20x faster than recorded (a frame every 1.7 ms, faster than any frame is processed):
// frames are dropped, each frame is processed or dropped, and the result folder is complete.
TEST(SlamRunner, ALiveStreamFasterThanThePipelineDropsFramesAndCountsThem) {
  SlamSystem system(quietOptions(), nullptr);
  const MemorySource frames(sequence());
  ClockedStream stream(frames, 20.0);
  const std::string out = testing::TempDir() + "pf2_runner_live";
  std::filesystem::remove_all(out);
  SlamRunner::Options runner;
  runner.progress = false;
  const SlamResult result = runToFolder(&system, &stream, out, runner);
  EXPECT_GT(result.summary.dropped, 0);
  EXPECT_EQ(result.summary.frames + result.summary.dropped, 45);
  EXPECT_FALSE(result.summary.stopped);
  EXPECT_EQ(readTrajectory(out + "/trajectory.txt").size(), static_cast<size_t>(result.summary.tracked));
}

// A stream that asks the run to stop after 10 frames, as Ctrl-C does.
class StoppingStream : public FrameStream {
 public:
  StoppingStream(const FrameSource& source, std::atomic<bool>* stop) : source_(source), stop_(stop) {}
  std::optional<Frame> next() override {
    if (next_ == 10) *stop_ = true;
    if (next_ >= source_.size()) return std::nullopt;
    return source_.frame(next_++);
  }
  void stop() override {}
  std::string description() const override { return "stopping"; }

 private:
  const FrameSource& source_;
  std::atomic<bool>* stop_;
  size_t next_ = 0;
};

TEST(SlamRunner, AStopRequestFinishesTheFramesInFlightAndWritesACompleteFolder) {
  for (const bool ahead : {true, false}) {
    std::atomic<bool> stop{false};
    SlamSystem system(quietOptions(), nullptr);
    StoppingStream stream(sequence(), &stop);
    const std::string out = testing::TempDir() + "pf2_runner_stopped";
    std::filesystem::remove_all(out);
    SlamRunner::Options runner;
    runner.progress = false;
    runner.detect_ahead = ahead;
    const SlamResult result = runToFolder(&system, &stream, out, runner, &stop);
    EXPECT_TRUE(result.summary.stopped);
    // The frame taken when the request came is still processed; none after it.
    EXPECT_GE(result.summary.frames, 10);
    EXPECT_LE(result.summary.frames, 11);
    EXPECT_EQ(readTrajectory(out + "/trajectory.txt").size(), static_cast<size_t>(result.summary.frames));
    EXPECT_TRUE(std::filesystem::exists(out + "/stats.json"));
  }
}

}  // namespace
}  // namespace pf2
