// FrameStreams: a recording decoded ahead gives every frame in order; a recording replayed on a
// clock drops (and counts) the frames a slow consumer does not take; stop() ends both; a TUM
// recording of frames reads back as the same frames.
#include <chrono>
#include <filesystem>
#include <thread>

#include <gtest/gtest.h>

#include "pf2/core/error.h"
#include "pf2/io/frame_streams.h"
#include "pf2/io/tum_recorder.h"
#include "pf2/io/tum_sequence.h"

namespace pf2 {
namespace {

// `count` small frames 1/30 s apart, each filled with its index.
class CountingSource : public FrameSource {
 public:
  explicit CountingSource(size_t count) : count_(count) {}
  size_t size() const override { return count_; }
  std::string description() const override { return "counting"; }
  Frame frame(size_t i) const override {
    Frame frame;
    frame.index = static_cast<int>(i);
    frame.timestamp = 100.0 + i / 30.0;
    frame.rgb = cv::Mat(24, 32, CV_8UC3, cv::Scalar(i % 256, 10, 200));
    frame.depth = cv::Mat(24, 32, CV_32F, cv::Scalar(0.5 + 0.01 * i));
    frame.intrinsics = CameraIntrinsics::tumFreiburg3().scaled(0.05);
    return frame;
  }

 private:
  size_t count_;
};

TEST(RecordedStream, EveryFrameInOrderThenTheEnd) {
  const CountingSource source(40);
  StageStats stats;
  RecordedStream stream(source, 25, 3, &stats);
  EXPECT_EQ(stream.expected(), 25u);
  for (int i = 0; i < 25; ++i) {
    std::optional<Frame> frame = stream.next();
    ASSERT_TRUE(frame);
    EXPECT_EQ(frame->index, i);
  }
  EXPECT_FALSE(stream.next());
  EXPECT_EQ(stream.dropped(), 0);
  EXPECT_EQ(stats.summary("load").count, 25);
  RecordedStream stopped(source, 0, 2, nullptr);
  ASSERT_TRUE(stopped.next());
  stopped.stop();
  EXPECT_FALSE(stopped.next());
}

// Replayed 10x faster than recorded (a frame every 3.3 ms) to a consumer that needs 20 ms per
// frame: most frames are dropped, the ones taken are in order, taken + dropped = all.
TEST(ClockedStream, DropsWhatASlowConsumerCannotTakeAndCountsIt) {
  const CountingSource source(60);
  ClockedStream stream(source, 10.0);
  int taken = 0, last = -1;
  while (std::optional<Frame> frame = stream.next()) {
    EXPECT_GT(frame->index, last);
    last = frame->index;
    ++taken;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_EQ(taken + stream.dropped(), 60);
  EXPECT_GT(stream.dropped(), 30);
  EXPECT_EQ(last, 59);  // the newest frame is never lost
}

TEST(ClockedStream, AFastConsumerGetsEveryFrameAtTheRecordedPace) {
  const CountingSource source(15);
  const auto start = std::chrono::steady_clock::now();
  ClockedStream stream(source, 1.0);
  int taken = 0;
  while (stream.next()) ++taken;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(taken, 15);
  EXPECT_EQ(stream.dropped(), 0);
  EXPECT_GE(seconds, 14 / 30.0 - 0.01);  // frame 14 is due 0.467 s after the start
}

TEST(TumRecorder, ARecordingReadsBackAsTheSameFrames) {
  const std::string folder = testing::TempDir() + "pf2_recording";
  std::filesystem::remove_all(folder);
  const CountingSource source(5);
  {
    TumRecorder recorder(folder);
    for (size_t i = 0; i < 5; ++i) recorder.add(source.frame(i));
    EXPECT_EQ(recorder.frames(), 5);
  }
  const TumSequence read(folder);
  ASSERT_EQ(read.size(), 5u);
  for (size_t i = 0; i < 5; ++i) {
    const Frame a = source.frame(i), b = read.frame(i);
    EXPECT_NEAR(b.timestamp, a.timestamp, 1e-6);
    EXPECT_EQ(cv::norm(a.rgb, b.rgb, cv::NORM_INF), 0.0);
    EXPECT_LT(cv::norm(a.depth, b.depth, cv::NORM_INF), 2e-4);  // 5000 units per metre
    EXPECT_NEAR(b.intrinsics.fx, a.intrinsics.fx, 1e-6);
  }
  // A second recording into the same folder would mix two: refused.
  EXPECT_THROW(TumRecorder again(folder), Error);
}

}  // namespace
}  // namespace pf2
