// pf2_detect: runs a person detector and the Dual-BBox filter over a TUM-layout sequence and
// writes the static depth (people removed), the removed-pixel masks and the boxes; with a
// pf2_synth sequence (gt/masks/) it also prints how much of the people was removed.
#include <sys/stat.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <iterator>
#include <regex>
#include <sstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "pf2/core/atomic_file.h"
#include "pf2/core/app_settings.h"
#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/core/stage_timer.h"
#include "pf2/detection/detector_factory.h"
#include "pf2/filters/dual_bbox_filter.h"
#include "pf2/core/settings.h"
#include "pf2/filters/filter_settings.h"
#include "pf2/filters/mask_metrics.h"
#include "pf2/filters/person_removal.h"
#include "pf2/io/image_file.h"
#include "pf2/io/tum_sequence.h"

namespace {

const char* kUsage =
    "Usage: pf2_detect SEQUENCE_DIR OUT_DIR [options]\n"
    "Detects people in every frame of a TUM-layout sequence, removes them from the depth with the\n"
    "Dual-BBox filter (paper Algorithm 1) and writes\n"
    "  OUT_DIR/static_depth/<depth name>.png  16-bit, metres x 5000, people removed\n"
    "  OUT_DIR/masks/<depth name>.png         8-bit, 255 = depth removed as a person's\n"
    "  OUT_DIR/boxes.txt                      timestamp x_ul y_ul x_lr y_lr score\n"
    "With SEQUENCE_DIR/gt/masks (pf2_synth) it prints recall of removed person pixels, precision\n"
    "of the kept depth and retention of static depth.\n"
    "\n"
    "Detector:\n"
    "  --detector NAME        gt | hog | file | yolo | selfie | movenet | learned (those built in;\n"
    "                         default gt when SEQUENCE_DIR/gt exists, else hog)\n"
    "  --gt-dir DIR           ground-truth folder (default SEQUENCE_DIR/gt)\n"
    "  --gt-mask              gt: hand the ground-truth person masks to the filter\n"
    "  --gt-misalign PX       depth lies PX pixels right of the gt masks, for the metrics (default:\n"
    "                         'misalignment N px' from gt/README.md, else 0)\n"
    "  --boxes FILE           file: boxes file (timestamp x_ul y_ul x_lr y_lr score)\n"
    "  --yolo-model FILE      yolo: .cfg (Darknet, with --yolo-weights) or .onnx (YOLOv5/v8)\n"
    "  --yolo-weights FILE    yolo: Darknet .weights\n"
    "  --yolo-size N          yolo: network input width = height (default 416)\n"
    "  --yolo-layout L        yolo: auto | darknet | v5 | v8 (default auto)\n"
    "  --hog-scale S          hog: image scale before detection (default 1.0)\n"
    "  --model FILE           model file of a plug-in backend (selfie, movenet)\n"
    "  --backend-options L    more plug-in backend options, 'key=value,key=value' (e.g.\n"
    "                         selfie.threshold=0.6; each backend documents its keys)\n"
    "Degradation of the detections (any detector; deterministic per frame; the boxes.* settings):\n"
    "  --shrink F             boxes lose fraction F of width and height (default 0)\n"
    "  --shift PX             boxes (and masks) move PX pixels in a random direction (default 0)\n"
    "  --drop P               each person is missed with probability P (default 0)\n"
    "  --false-positives R    R false boxes per frame on average (default 0)\n"
    "  --seed N               random seed (default 1)\n"
    "Filter (defaults are the paper's; the filter.* keys of docs/config.md, same meaning):\n"
    "  --config FILE          'key value' lines (filter.* and boxes.* keys)\n"
    "  --set KEY=VALUE        one setting, after --config (repeatable), e.g.\n"
    "                         --set filter.use_mask=true --set filter.temporal=true (the temporal guard\n"
    "                         moves last frame's pixels by groundtruth.txt's motion) --set\n"
    "                         filter.geometric=true (depth in front of the farthest static depth seen\n"
    "                         so far, a stand-in for the prediction pf2_slam makes from its keyframes)\n"
    "  --settings             print the settings (key, default, unit, range, meaning) and exit\n"
    "  --no-filter            write the input depth with the boxes' pixels removed (boxes only)\n"
    "Other:\n"
    "  --max-frames N         process the first N frames only\n"
    "  --json                 print one JSON object as the last line\n"
    "  -h, --help             this text\n"
    "Exit status: 0 on success, 1 on bad input (one error line naming the file).\n";

// pf2_synth names the depth shift in gt/README.md ("misalignment 3 px"); 0 when absent.
int misalignmentFromReadme(const std::string& gt_dir) {
  std::ifstream in(gt_dir + "/README.md");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::smatch match;
  if (std::regex_search(text, match, std::regex("misalignment (-?[0-9]+) px"))) return std::stoi(match[1]);
  return 0;
}

// Moves a mask dx pixels right (left for negative dx), zero where nothing moved in.
bool exists(const std::string& path) {
  struct stat s;
  return ::stat(path.c_str(), &s) == 0;
}

void makeDirectory(const std::string& path) {
  if (::mkdir(path.c_str(), 0755) != 0 && !exists(path)) throw pf2::fileError(path, "cannot create folder");
}

std::string baseName(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

cv::Mat toTumDepth(const cv::Mat& depth_m) {
  cv::Mat out;
  depth_m.convertTo(out, CV_16U, 5000.0, 0.5);  // saturates beyond 13.1 m
  return out;
}

// Everything the command line says, gathered so setup, the frame loop and the report share it.
struct DetectOptions {
  std::string detector_name;  // empty: chosen in DetectSetup (gt when gt/boxes.txt exists, else hog)
  pf2::DetectorOptions detector;
  std::string gt_dir_option;
  std::optional<std::string> misalign_option;
  pf2::BoxDegradation degradation;
  pf2::DualBBoxFilter::Options filter;
  bool no_filter = false;
  int max_frames = 0;
  bool as_json = false;
  std::string sequence_dir;
  std::string out_dir;
};

// Reads --detector .. --backend-options into `options`, in the order run() always read them.
void parseDetectorOptions(pf2::CommandLine& cli, DetectOptions* options) {
  options->detector_name = cli.value("--detector", "");
  pf2::DetectorOptions& detector_options = options->detector;
  options->gt_dir_option = cli.value("--gt-dir", "");
  options->misalign_option = cli.value("--gt-misalign");
  detector_options.gt.provide_mask = cli.flag("--gt-mask");
  detector_options.file.path = cli.value("--boxes", "");
  detector_options.yolo.model = cli.value("--yolo-model", "");
  detector_options.yolo.weights = cli.value("--yolo-weights", "");
  detector_options.yolo.input_width = detector_options.yolo.input_height = cli.integer("--yolo-size", 416);
  detector_options.yolo.layout = cli.value("--yolo-layout", "auto");
  detector_options.hog.image_scale = cli.number("--hog-scale", 1.0);
  if (const auto model = cli.value("--model")) detector_options.extra["model"] = *model;
  if (const auto list = cli.value("--backend-options")) {
    std::stringstream items(*list);
    std::string item;
    while (std::getline(items, item, ',')) {
      const auto equals = item.find('=');
      if (equals == std::string::npos || equals == 0) {
        throw pf2::Error("--backend-options: expected key=value, got '" + item + "'");
      }
      detector_options.extra[item.substr(0, equals)] = item.substr(equals + 1);
    }
  }
}

// The settings pf2_detect reads: the Dual-BBox filter's (filter.*) and the box degradation's
// (boxes.*), the latter also as the options --shrink .. --seed.
pf2::Settings declareDetectSettings(DetectOptions* options) {
  pf2::Settings settings;
  pf2::declareFilterSettings(&options->filter, &settings);
  pf2::declareBoxDegradationSettings("boxes.", &options->degradation, &settings);
  return settings;
}

void readDetectSettings(pf2::CommandLine& cli, DetectOptions* options) {
  pf2::Settings settings = declareDetectSettings(options);
  pf2::readCommandLineSettings(&cli, &settings,
                               {{"--shrink", "boxes.shrink"},
                                {"--shift", "boxes.shift"},
                                {"--drop", "boxes.drop"},
                                {"--false-positives", "boxes.false_positives"},
                                {"--seed", "boxes.seed"}});
}

// Reads all options first, then the two folders (positionals() rejects any option left unread).
DetectOptions parseOptions(pf2::CommandLine& cli) {
  DetectOptions options;
  parseDetectorOptions(cli, &options);
  readDetectSettings(cli, &options);
  options.no_filter = cli.flag("--no-filter");
  options.max_frames = cli.integer("--max-frames", 0);
  options.as_json = cli.flag("--json");
  const auto folders = cli.positionals();
  if (folders.size() != 2) {
    throw pf2::Error("expected SEQUENCE_DIR and OUT_DIR, got " + std::to_string(folders.size()) +
                     " folder argument(s) (see -h)");
  }
  options.sequence_dir = folders[0];
  options.out_dir = folders[1];
  return options;
}

// Picks the default detector (gt when gt_dir has boxes, else hog) into options and creates it.
std::unique_ptr<pf2::HumanDetector> createDetector(DetectOptions* options, const std::string& gt_dir) {
  if (options->detector_name.empty()) options->detector_name = exists(gt_dir + "/boxes.txt") ? "gt" : "hog";
  options->detector.gt.gt_folder = gt_dir;
  return pf2::createHumanDetector(options->detector_name, options->detector);
}

// The person removal pf2_detect runs: the filter and degradation from the command line, the
// geometric addition's evidence with its plain defaults (0.15 m, no opening) fed by the stand-in model.
pf2::PersonRemoval::Options removalOptions(const DetectOptions& options) {
  pf2::PersonRemoval::Options removal;
  removal.filter = options.filter;
  removal.degradation = options.degradation;
  return removal;
}

// The sequence, detector, filter and ground truth one run works with, opened in this order.
struct DetectSetup {
  explicit DetectSetup(DetectOptions* options);

  const pf2::TumSequence sequence;
  const std::string gt_dir;
  pf2::PersonRemoval removal;  // the detector and the filter, as pf2_slam runs them
  pf2::Trajectory poses;       // groundtruth.txt, empty without it
  bool have_masks = false;                                // gt/masks exists: score the removal
  int misalign = 0;                                       // depth lies this many pixels right of gt
};

// Opens the sequence, creates the detector and filter, and reads the ground truth that exists.
DetectSetup::DetectSetup(DetectOptions* options)
    : sequence(options->sequence_dir),
      gt_dir(options->gt_dir_option.empty() ? options->sequence_dir + "/gt" : options->gt_dir_option),
      removal(removalOptions(*options), createDetector(options, gt_dir)) {
  poses = sequence.hasGroundTruth() ? sequence.groundTruth() : pf2::Trajectory();
  have_masks = exists(gt_dir + "/masks");
  misalign = misalignmentFromReadme(gt_dir);
  if (options->misalign_option) misalign = std::stoi(*options->misalign_option);
}

// What the frame loop gathers for the report and boxes.txt.
struct DetectTotals {
  size_t frames = 0;
  pf2::StageStats stats;
  pf2::MaskCounts counts;
  std::vector<pf2::Detections> all_detections;
};

// Removes the people from one frame's depth: the boxes cut out (--no-filter) or the Dual-BBox filter.
void removePeople(const DetectOptions& options, DetectSetup& setup, const pf2::Frame& frame,
                  const pf2::Detections& detections, const Eigen::Isometry3d& T_cur_prev, const cv::Mat& predicted,
                  pf2::StageStats* stats, cv::Mat* static_depth, cv::Mat* removed) {
  if (options.no_filter) {
    *static_depth = frame.depth.clone();
    for (const auto& p : detections.people) {
      if (p.score > options.filter.min_confidence) {
        (*static_depth)(pf2::scaledBoxRect(p.box, 1.0, static_depth->size())).setTo(0.f);
      }
    }
    *removed = (frame.depth > 0) & (*static_depth == 0);
  } else {
    pf2::DualBBoxFilter::Result result = setup.removal.filter(frame, detections, T_cur_prev, predicted, stats);
    *static_depth = result.static_depth;
    *removed = result.removed;
  }
}

// Writes frame i's static depth and removed mask; with gt masks adds their agreement to counts.
void writeAndScoreFrame(const DetectOptions& options, const DetectSetup& setup, size_t i, const pf2::Frame& frame,
                        const cv::Mat& static_depth, const cv::Mat& removed, pf2::MaskCounts* counts) {
  const std::string name = baseName(setup.sequence.files(i).depth.file);
  pf2::writeImageFile(options.out_dir + "/static_depth/" + name, toTumDepth(static_depth));
  pf2::writeImageFile(options.out_dir + "/masks/" + name, removed);
  if (setup.have_masks) {
    const std::string mask_path = setup.gt_dir + "/masks/" + name;
    const cv::Mat gt = pf2::readImageFile(mask_path, cv::IMREAD_UNCHANGED, "ground-truth mask", frame.depth.size());
    if (gt.size() != frame.depth.size() || gt.channels() != 1) {
      throw pf2::fileError(mask_path, "ground-truth mask is not single-channel of the depth's size");
    }
    *counts += pf2::countMaskAgreement(frame.depth, static_depth, pf2::shiftMaskRight(gt, setup.misalign));
  }
}

// Detects, filters, writes and scores each frame in order, carrying camera motion and the --geometric model along.
void processFrames(const DetectOptions& options, DetectSetup& setup, DetectTotals* totals) {
  Eigen::Isometry3d T_w_prev = Eigen::Isometry3d::Identity();
  bool have_previous_pose = false;
  cv::Mat static_model;  // --geometric: farthest static depth seen, in the previous frame's view
  const size_t frames = options.max_frames > 0 ? std::min<size_t>(setup.sequence.size(), options.max_frames)
                                               : setup.sequence.size();
  totals->frames = frames;
  for (size_t i = 0; i < frames; ++i) {
    const pf2::Frame frame = setup.sequence.frame(i);
    const pf2::Detections detections = setup.removal.detect(frame, &totals->stats);
    totals->all_detections.push_back(detections);

    // Camera motion since the last frame, from groundtruth.txt (in the SLAM pipeline: odometry).
    Eigen::Isometry3d T_cur_prev = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_w_cur;
    const bool have_pose = !setup.poses.empty() && pf2::interpolateAt(setup.poses, frame.timestamp, 0.1, &T_w_cur);
    if (have_pose && have_previous_pose) T_cur_prev = T_w_cur.inverse() * T_w_prev;
    cv::Mat predicted;
    if (options.filter.geometric && !static_model.empty()) {
      predicted = pf2::warpDepth(static_model, frame.intrinsics, T_cur_prev);
    }
    cv::Mat static_depth, removed;
    removePeople(options, setup, frame, detections, T_cur_prev, predicted, &totals->stats, &static_depth, &removed);
    if (options.filter.geometric) {
      // People only ever stand in front of the static scene, so the farthest depth seen is static.
      static_model = predicted.empty() ? static_depth.clone() : cv::max(predicted, static_depth);
    }
    T_w_prev = T_w_cur;
    have_previous_pose = have_pose;
    writeAndScoreFrame(options, setup, i, frame, static_depth, removed, &totals->counts);
  }
}

// Prints frames, detector, timings and (with gt masks) the removal scores; --json adds one line.
void printReport(const DetectOptions& options, const DetectSetup& setup, const DetectTotals& totals) {
  const size_t frames = totals.frames;
  const pf2::MaskCounts& counts = totals.counts;
  const std::string& detector_name = options.detector_name;
  const pf2::StageSummary det = totals.stats.summary("detect"), fil = totals.stats.summary("filter");
  std::printf("frames           %zu\n", frames);
  std::printf("detector         %s\n", detector_name.c_str());
  std::printf("detector.ms      median %.3f  p90 %.3f  mean %.3f\n", det.median_ms, det.p90_ms, det.mean_ms);
  if (!options.no_filter) std::printf("filter.ms        median %.3f  p90 %.3f  mean %.3f\n", fil.median_ms, fil.p90_ms, fil.mean_ms);
  if (setup.have_masks) {
    std::printf("recall           %.5f  (person pixels removed / person pixels with depth)\n", counts.recall());
    std::printf("precision        %.5f  (static pixels kept / pixels kept)\n", counts.precision());
    std::printf("retention        %.5f  (static pixels kept / static pixels with depth)\n", counts.retention());
  }
  if (options.as_json) {
    std::printf("{\"frames\":%zu,\"detector\":\"%s\",\"detector_median_ms\":%.4f,\"filter_median_ms\":%.4f",
                frames, detector_name.c_str(), det.median_ms, fil.median_ms);
    if (setup.have_masks) {
      std::printf(",\"recall\":%.6f,\"precision\":%.6f,\"retention\":%.6f", counts.recall(), counts.precision(),
                  counts.retention());
    }
    std::printf("}\n");
  }
}

// Parses, sets up, runs the frames, writes boxes.txt and prints the report (see kUsage).
int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  DetectOptions defaults;
  if (pf2::answeredHelpOrSettings(&cli, kUsage, declareDetectSettings(&defaults))) return 0;
  DetectOptions options = parseOptions(cli);
  DetectSetup setup(&options);

  makeDirectory(options.out_dir);
  makeDirectory(options.out_dir + "/static_depth");
  makeDirectory(options.out_dir + "/masks");

  DetectTotals totals;
  processFrames(options, setup, &totals);
  pf2::writeBoxesFile(options.out_dir + "/boxes.txt", totals.all_detections);
  printReport(options, setup, totals);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_detect", run, argc, argv); }
