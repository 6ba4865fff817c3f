#include "pf2/io/frame_streams.h"

#include <algorithm>
#include <chrono>

namespace pf2 {

RecordedStream::RecordedStream(const FrameSource& source, size_t count, int prefetch, StageStats* stats)
    : source_(source),
      count_(count == 0 ? source.size() : std::min(count, source.size())),
      queue_(static_cast<size_t>(std::max(1, prefetch))),
      thread_([this, stats] { load(stats); }) {}

RecordedStream::~RecordedStream() { stop(); }

void RecordedStream::load(StageStats* stats) {
  for (size_t i = 0; i < count_ && !stopped_; ++i) {
    Loaded item;
    try {
      if (stats != nullptr) {
        ScopedStageTimer timer(stats, "load");
        item.frame = source_.frame(i);
      } else {
        item.frame = source_.frame(i);
      }
    } catch (...) {
      item.error = std::current_exception();
    }
    const bool failed = static_cast<bool>(item.error);
    queue_.push(std::move(item));
    if (failed) break;
  }
  queue_.close();
}

std::optional<Frame> RecordedStream::next() {
  if (stopped_) return std::nullopt;
  std::optional<Loaded> item = queue_.pop();
  if (!item) return std::nullopt;
  if (item->error) std::rethrow_exception(item->error);
  return std::move(item->frame);
}

void RecordedStream::stop() {
  stopped_ = true;
  queue_.close();
  if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
}

void LatestFrameSlot::put(Frame frame) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (latest_) ++dropped_;
  latest_ = std::move(frame);
  changed_.notify_one();
}

void LatestFrameSlot::fail(std::exception_ptr error) {
  std::lock_guard<std::mutex> lock(mutex_);
  error_ = error;
  changed_.notify_all();
}

void LatestFrameSlot::close() {
  std::lock_guard<std::mutex> lock(mutex_);
  closed_ = true;
  changed_.notify_all();
}

void LatestFrameSlot::stop() {
  std::lock_guard<std::mutex> lock(mutex_);
  stopped_ = true;
  changed_.notify_all();
}

std::optional<Frame> LatestFrameSlot::take() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return latest_.has_value() || closed_ || error_ || stopped_; });
  if (error_) std::rethrow_exception(error_);
  if (stopped_ || !latest_) return std::nullopt;
  std::optional<Frame> frame = std::move(latest_);
  latest_.reset();
  return frame;
}

ClockedStream::ClockedStream(const FrameSource& source, double speed)
    : source_(source), thread_([this, speed] { deliver(speed); }) {}

ClockedStream::~ClockedStream() { stop(); }

// Decodes each frame, waits for its time to come, then hands it over (a frame the consumer did not
// take in time is replaced and counted).
void ClockedStream::deliver(double speed) {
  const auto start = std::chrono::steady_clock::now();
  double first_stamp = 0;
  for (size_t i = 0; i < source_.size() && !stopped_; ++i) {
    Frame frame;
    try {
      frame = source_.frame(i);
    } catch (...) {
      slot_.fail(std::current_exception());
      return;
    }
    if (i == 0) first_stamp = frame.timestamp;
    std::this_thread::sleep_until(start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                              std::chrono::duration<double>((frame.timestamp - first_stamp) / speed)));
    slot_.put(std::move(frame));
  }
  slot_.close();
}

void ClockedStream::stop() {
  stopped_ = true;
  slot_.stop();
  if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
}

}  // namespace pf2
