#pragma once
// SlamRunner: the frame loop. Frames of a FrameStream (a recording decoded ahead, a recording
// replayed in real time, a live camera) go through a SlamSystem; the detection of the next frame
// runs in a thread of its own while the front end filters and tracks this one, so the two largest
// costs of a frame overlap on two cores. A progress line, and an early stop that still finishes
// the frames in flight and returns a complete result.
//
// Threads: run() starts the detection thread (SlamSystem::detect, frames in order) and runs the
// front end (SlamSystem::process) on the calling thread; a queue of two frames sits between them,
// so a slow front end holds detection back and a live stream drops frames, never the pipeline.
// NOT thread safe: one run() at a time.
#include <atomic>
#include <string>

#include "pf2/core/frame_source.h"
#include "pf2/slam/slam_system.h"

namespace pf2 {

class SlamRunner {
 public:
  struct Options {
    bool detect_ahead = true;  // detection in its own thread, one frame ahead (false: in process())
    bool progress = true;      // a progress line on standard error every 30 frames
  };

  // The system must outlive the runner.
  SlamRunner(SlamSystem* system, const Options& options) : system_(system), options_(options) {}

  // Runs until the stream ends or *stop turns true (checked before each frame is taken), then
  // SlamSystem::finish(). The summary counts the frames the stream dropped and says whether the
  // run was stopped. Rethrows the first error of either thread after both have stopped.
  SlamResult run(FrameStream* stream, const std::atomic<bool>* stop = nullptr);

 private:
  void processAll(FrameStream* stream, const std::atomic<bool>* stop);
  void showProgress(size_t expected, int dropped, double seconds) const;

  SlamSystem* system_;
  Options options_;
};

// Creates out_dir when missing (its parent must exist); throws pf2::Error naming it otherwise.
void makeOutputFolder(const std::string& out_dir);

// A whole run into a result folder, as pf2_slam makes it: the stream through the system (each
// frame's removed mask into masks/ when options().write_masks and the system removes people),
// then writeSlamResult() with `extra_files` in the same set. A run that fails leaves out_dir as it
// was (masks/ included). out_dir is created when missing.
SlamResult runToFolder(SlamSystem* system, FrameStream* stream, const std::string& out_dir,
                       const SlamRunner::Options& options, const std::atomic<bool>* stop = nullptr,
                       const ExtraFiles& extra_files = nullptr);

}  // namespace pf2
