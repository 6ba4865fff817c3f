#pragma once
// "file" backend: boxes from a text file, so that any external detector can be plugged in.
// One line per box: "timestamp x_ul y_ul x_lr y_lr score" (pixels, score in [0, 1]); '#' starts a
// comment; several lines may share a timestamp. pf2_detect writes the same format (boxes.txt).
#include <map>
#include <string>
#include <vector>

#include "pf2/detection/human_detector.h"

namespace pf2 {

// Reads a boxes file. Throws pf2::Error "path:line: ..." on a malformed line or naming the file
// when it cannot be opened. Thread safe.
std::map<double, std::vector<PersonDetection>> readBoxesFile(const std::string& path);
// Writes all detections in that format (6 decimals for stamps, 2 for pixels), atomically.
void writeBoxesFile(const std::string& path, const std::vector<Detections>& detections);

class FileDetector : public HumanDetector {
 public:
  struct Options {
    std::string path;                   // the boxes file
    double max_time_difference = 0.02;  // seconds between a frame and the nearest stamp in the file
  };
  explicit FileDetector(const Options& options);  // reads the file (see readBoxesFile)

  std::string name() const override { return "file"; }
  // The boxes of the nearest stamp within max_time_difference, none otherwise. Thread safe.
  Detections detect(const Frame& frame) override;

 private:
  Options options_;
  std::map<double, std::vector<PersonDetection>> boxes_;
};

}  // namespace pf2
