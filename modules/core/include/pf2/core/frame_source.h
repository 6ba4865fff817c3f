#pragma once
// Where frames come from (a TUM folder, a synthetic scene, a sensor): the pipeline reads only this.
#include <cstddef>
#include <optional>
#include <string>

#include "pf2/core/frame.h"

namespace pf2 {

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  // Number of frames; frames are addressed 0 .. size()-1.
  virtual size_t size() const = 0;
  // Loads frame i. Throws pf2::Error naming the file on unreadable input. Thread safe.
  virtual Frame frame(size_t i) const = 0;
  // A short description for logs ("TUM folder X", "synthetic xyz, 3 people").
  virtual std::string description() const = 0;
};

// Frames one after the other, as a run consumes them: a recorded sequence decoded ahead, a
// recording replayed at its own pace, a live camera. NOT thread safe: one consumer.
class FrameStream {
 public:
  virtual ~FrameStream() = default;
  // The next frame, nullopt after the last one (or once stop() was called). Throws pf2::Error
  // naming the file or device on a decoding or device error.
  virtual std::optional<Frame> next() = 0;
  // Ends the stream early: next() returns nullopt from now on. Thread safe (another thread may
  // call it while next() waits); not for signal handlers (set a flag there and call it after).
  virtual void stop() = 0;
  // Frames the stream will deliver when known (a recording), 0 when not (a live camera).
  virtual size_t expected() const { return 0; }
  // Frames that arrived while the consumer was still busy and were replaced by newer ones before
  // it took them (real-time streams; 0 for a recording read frame by frame).
  virtual int dropped() const { return 0; }
  virtual std::string description() const = 0;
};

}  // namespace pf2
