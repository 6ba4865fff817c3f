#pragma once
// "gt" backend: the people pf2_synth rendered, read from a sequence's gt/ folder (gt/boxes.txt,
// gt/masks/<stamp>.png; see docs/detection.md for the format), optionally degraded. Boxes and masks
// are those of the colour image (pf2_synth --misalign shifts the depth, not them).
#include <map>
#include <string>
#include <vector>

#include "pf2/detection/box_degradation.h"
#include "pf2/detection/human_detector.h"

namespace pf2 {

class GtDetector : public HumanDetector {
 public:
  struct Options {
    std::string gt_folder;             // the sequence's gt/ folder
    bool provide_mask = false;         // attach each person's ground-truth mask (reads gt/masks/)
    double min_visible_fraction = 0.0; // people less visible than this are not reported, 0..1
    double max_time_difference = 0.02; // seconds between a frame and its gt stamp
    BoxDegradation degradation;        // none by default
  };

  // Reads gt/boxes.txt (and lists gt/masks/ when provide_mask). Throws pf2::Error "file:line: ..."
  // on a malformed line, naming the file when it is missing.
  explicit GtDetector(const Options& options);

  std::string name() const override { return "gt"; }
  // Boxes of the gt stamp nearest the frame's timestamp (none when farther than
  // max_time_difference); score 1. The file's inclusive corners become PersonBox's exclusive ones
  // (x_lr + 1, y_lr + 1). Throws pf2::Error naming the mask file when it is unreadable or
  // of the wrong size/type. NOT thread safe.
  Detections detect(const Frame& frame) override;

 private:
  struct Entry {
    int id = 0;
    PersonBox box;
    double visible_fraction = 1.0;
  };
  Options options_;
  std::map<double, std::vector<Entry>> boxes_;  // by timestamp
  std::map<double, std::string> mask_files_;    // by timestamp
};

}  // namespace pf2
