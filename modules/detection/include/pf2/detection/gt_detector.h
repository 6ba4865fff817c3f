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

// One line of pf2_synth's gt/boxes.txt: a person in view of one frame.
struct GroundTruthBox {
  double timestamp = 0;
  int id = 0;
  PersonBox box;                  // exclusive lower right: the file's inclusive corners + 1
  double visible_fraction = 1.0;  // 0..1
};

// Reads gt/boxes.txt (`timestamp id x_ul y_ul x_lr y_lr visible_fraction` lines, `#` comments).
// Throws pf2::Error "file:line: ..." on a malformed, non-finite or out-of-order line, naming the
// file when it is missing. Thread safe.
std::vector<GroundTruthBox> readGroundTruthBoxes(const std::string& path);

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
  Options options_;
  std::map<double, std::vector<GroundTruthBox>> boxes_;  // by timestamp
  std::map<double, std::string> mask_files_;    // by timestamp
};

}  // namespace pf2
