#include "pf2/detection/file_detector.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "nearest_stamp.h"
#include "pf2/core/text_lines.h"
#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"

namespace pf2 {

std::map<double, std::vector<PersonDetection>> readBoxesFile(const std::string& path) {
  std::map<double, std::vector<PersonDetection>> boxes;
  forEachDataLine(path, "boxes file", [&](const std::string& line, int number) {
    std::istringstream fields(line);
    double stamp = 0;
    PersonDetection p;
    if (!(fields >> stamp >> p.box.x_ul >> p.box.y_ul >> p.box.x_lr >> p.box.y_lr >> p.score)) {
      throw fileError(path, number, "expected 'timestamp x_ul y_ul x_lr y_lr score'");
    }
    if (!std::isfinite(stamp) || !std::isfinite(p.box.x_ul) || !std::isfinite(p.box.y_ul) ||
        !std::isfinite(p.box.x_lr) || !std::isfinite(p.box.y_lr) || !std::isfinite(p.score)) {
      throw fileError(path, number, "non-finite number");
    }
    if (p.score < 0 || p.score > 1) throw fileError(path, number, "score outside [0, 1]");
    if (p.box.x_lr < p.box.x_ul || p.box.y_lr < p.box.y_ul) {
      throw fileError(path, number, "box corners out of order (x_lr < x_ul or y_lr < y_ul)");
    }
    boxes[stamp].push_back(p);
  });
  return boxes;
}

void writeBoxesFile(const std::string& path, const std::vector<Detections>& detections) {
  writeFileAtomically(path, [&](std::ostream& out) {
    out << "# timestamp x_ul y_ul x_lr y_lr score\n";
    char buffer[160];
    for (const Detections& d : detections) {
      for (const PersonDetection& p : d.people) {
        std::snprintf(buffer, sizeof(buffer), "%.6f %.2f %.2f %.2f %.2f %.4f\n", d.timestamp, p.box.x_ul,
                      p.box.y_ul, p.box.x_lr, p.box.y_lr, p.score);
        out << buffer;
      }
    }
  });
}

FileDetector::FileDetector(const Options& options) : options_(options), boxes_(readBoxesFile(options.path)) {}

Detections FileDetector::detect(const Frame& frame) {
  Detections detections;
  detections.timestamp = frame.timestamp;
  if (const auto* people = nearestStamp(boxes_, frame.timestamp, options_.max_time_difference)) {
    detections.people = *people;
  }
  return detections;
}

}  // namespace pf2
