// Scores the person removal of a pf2_slam run (its --masks output) against a pf2_synth sequence's
// ground-truth person masks: recall (person depth removed), precision and retention (static depth
// kept), as pf2_detect reports them for its own filter runs.
#include <cstdio>
#include <iostream>

#include <opencv2/imgcodecs.hpp>

#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/filters/mask_metrics.h"
#include "pf2/io/tum_sequence.h"

namespace {

const char* kUsage =
    "Usage: pf2_removal_score SEQUENCE_DIR MASK_DIR [--misalign PX] [--json]\n"
    "Scores MASK_DIR/<timestamp>.png (pf2_slam --masks: 255 = depth removed) against\n"
    "SEQUENCE_DIR/gt/masks/<timestamp>.png (pf2_synth). --misalign PX: the depth lies PX pixels\n"
    "right of the ground-truth masks (pf2_synth --misalign). Frames without a mask count as\n"
    "nothing removed. --json prints one JSON object (recall, precision, retention, frames).\n";

std::string stampName(double t) {
  char name[64];
  std::snprintf(name, sizeof(name), "%.6f.png", t);
  return name;
}

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  if (cli.helpRequested()) {
    std::cout << kUsage;
    return 0;
  }
  const int misalign = cli.integer("--misalign", 0);
  const bool as_json = cli.flag("--json");
  const auto paths = cli.positionals();
  if (paths.size() != 2) throw pf2::Error("expected SEQUENCE_DIR and MASK_DIR (see -h)");
  const pf2::TumSequence sequence(paths[0]);
  pf2::MaskCounts counts;
  for (size_t i = 0; i < sequence.size(); ++i) {
    const pf2::Frame frame = sequence.frame(i);
    const std::string name = stampName(frame.timestamp);
    const std::string gt_path = paths[0] + "/gt/masks/" + name;
    const cv::Mat gt = cv::imread(gt_path, cv::IMREAD_UNCHANGED);
    if (gt.empty()) throw pf2::fileError(gt_path, "cannot read the ground-truth mask");
    const cv::Mat removed = cv::imread(paths[1] + "/" + name, cv::IMREAD_GRAYSCALE);
    cv::Mat static_depth = frame.depth.clone();
    if (!removed.empty()) static_depth.setTo(0.0f, removed);
    counts += pf2::countMaskAgreement(frame.depth, static_depth, pf2::shiftMaskRight(gt, misalign));
  }
  if (as_json) {
    std::printf("{\"recall\":%.6f,\"precision\":%.6f,\"retention\":%.6f,\"frames\":%zu}\n", counts.recall(),
                counts.precision(), counts.retention(), sequence.size());
  } else {
    std::printf("recall     %.4f\nprecision  %.4f\nretention  %.4f\nframes     %zu\n", counts.recall(),
                counts.precision(), counts.retention(), sequence.size());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_removal_score", run, argc, argv); }
