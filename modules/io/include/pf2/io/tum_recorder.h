#pragma once
// Writes frames as they come into a TUM RGB-D folder that pf2_slam reads back as it reads any
// recording: rgb/<stamp>.png (8-bit colour), depth/<stamp>.png (16-bit, 5000 units per metre),
// rgb.txt, depth.txt (`timestamp file` lines, 6 decimals) and camera.txt (the first frame's
// intrinsics, CameraIntrinsics::save format). The lists are flushed after every frame, so a
// recording cut short (Ctrl-C, power) is readable up to its last complete frame.
// NOT thread safe: one writer.
#include <fstream>
#include <string>

#include "pf2/core/frame.h"

namespace pf2 {

class TumRecorder {
 public:
  // Creates `folder` (its parent must exist); it must be new or empty. Throws pf2::Error naming it.
  explicit TumRecorder(const std::string& folder);

  // Appends one frame. Throws pf2::Error naming the file that could not be written.
  void add(const Frame& frame);
  int frames() const { return frames_; }

 private:
  std::string folder_;
  std::ofstream rgb_list_, depth_list_;
  int frames_ = 0;
};

}  // namespace pf2
