#pragma once
// FrameStreams over recorded frames (pf2/core/frame_source.h):
//   RecordedStream — every frame of a FrameSource in order, decoded ahead in a loader thread
//                    (offline: nothing is dropped, the run takes as long as it takes);
//   ClockedStream  — the frames of a FrameSource delivered at the pace of their timestamps by a
//                    thread of its own, the way a camera delivers them: a frame the consumer has
//                    not taken when the next one arrives is replaced and counted as dropped. It
//                    is the live path without a camera (tests, and replaying a recording in real
//                    time).
// Both: next() from one consumer thread; stop() from anywhere.
#include <atomic>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

#include "pf2/core/frame_source.h"
#include "pf2/core/stage_timer.h"
#include "pf2/core/work_queue.h"

namespace pf2 {

// The one-frame hand-over of a real-time stream: a producer thread puts each frame as it arrives,
// replacing (and counting) one the consumer has not taken yet; the consumer waits for the next.
// Thread safe.
class LatestFrameSlot {
 public:
  void put(Frame frame);
  // The producer failed: take() rethrows the error.
  void fail(std::exception_ptr error);
  // No more frames: take() returns nullopt once the slot is empty (at once after stop()).
  void close();
  void stop();
  std::optional<Frame> take();
  int dropped() const { return dropped_; }

 private:
  std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<Frame> latest_;
  std::exception_ptr error_;
  bool closed_ = false, stopped_ = false;
  std::atomic<int> dropped_{0};
};

class RecordedStream : public FrameStream {
 public:
  // The first `count` frames of `source` (all when 0 or more than it has), `prefetch` decoded ahead;
  // decoding time goes to `stats` as "load" (may be null). source and stats must outlive the stream.
  RecordedStream(const FrameSource& source, size_t count, int prefetch, StageStats* stats);
  ~RecordedStream() override;

  std::optional<Frame> next() override;
  void stop() override;
  size_t expected() const override { return count_; }
  std::string description() const override { return source_.description(); }

 private:
  struct Loaded {
    Frame frame;
    std::exception_ptr error;
  };
  void load(StageStats* stats);

  const FrameSource& source_;
  const size_t count_;
  WorkQueue<Loaded> queue_;
  std::atomic<bool> stopped_{false};
  std::thread thread_;
};

class ClockedStream : public FrameStream {
 public:
  // Frame i becomes available (timestamp_i - timestamp_0) / speed seconds after the stream was
  // made; speed 1 = real time. source must outlive the stream.
  ClockedStream(const FrameSource& source, double speed = 1.0);
  ~ClockedStream() override;

  std::optional<Frame> next() override { return slot_.take(); }
  void stop() override;
  size_t expected() const override { return source_.size(); }
  int dropped() const override { return slot_.dropped(); }
  std::string description() const override { return source_.description() + ", replayed in real time"; }

 private:
  void deliver(double speed);

  const FrameSource& source_;
  LatestFrameSlot slot_;
  std::atomic<bool> stopped_{false};
  std::thread thread_;
};

}  // namespace pf2
