#pragma once
// Where frames come from (a TUM folder, a synthetic scene, a sensor): the pipeline reads only this.
#include <cstddef>
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

}  // namespace pf2
