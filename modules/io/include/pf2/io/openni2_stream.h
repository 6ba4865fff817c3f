#pragma once
// A live OpenNI2 RGB-D camera (Kinect for Xbox 360 through OpenNI2's drivers, Asus Xtion, Orbbec
// Astra, ...) or an OpenNI2 recording (.oni), as a FrameStream, through PCL's OpenNI2 grabber:
// colour and depth registered to colour and synchronised by the driver, VGA at 30 Hz. Frames arrive
// in the grabber's thread and are handed over in real time (LatestFrameSlot): a frame the pipeline
// has not taken when the next one arrives is dropped and counted. Optionally every frame that
// arrives is also recorded as a TUM folder (TumRecorder), in the grabber's thread.
//
// Thread safety: next() from one consumer; stop() from anywhere.
#include <memory>
#include <string>

#include "pf2/core/frame_source.h"

namespace pf2 {

class OpenNI2Stream : public FrameStream {
 public:
  // device: "" = the first camera found; an OpenNI2 URI or "#N" (the N-th camera); a path ending in
  // ".oni" = a recording. record_dir: "" = no recording, else a new (or empty) folder for a TUM
  // recording of every frame. Throws pf2::Error naming the device (or folder) when it cannot be
  // opened, or when this build has no OpenNI2 support.
  OpenNI2Stream(const std::string& device, const std::string& record_dir);
  ~OpenNI2Stream() override;

  std::optional<Frame> next() override;
  void stop() override;
  int dropped() const override;
  std::string description() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pf2
