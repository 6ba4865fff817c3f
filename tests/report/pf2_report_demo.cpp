// Runs the pipeline on a TUM-layout folder (e.g. a pf2_synth sequence) and writes the run's
// report.html, as pf2_slam does once it writes the report: the source of docs/images/report.png.
// Not a test; built with them because it is the report's demo.
//
//   pf2_report_demo SEQUENCE_DIR OUT.html [--set key=value ...]
#include <cstdio>
#include <exception>
#include <string>

#include "pf2/core/error.h"
#include "pf2/io/tum_sequence.h"
#include "pf2/report/run_report.h"
#include "pf2/slam/slam_options.h"
#include "pf2/slam/slam_system.h"

namespace {

int run(int argc, char** argv) {
  if (argc < 3) throw pf2::Error("usage: pf2_report_demo SEQUENCE_DIR OUT.html [--set key=value ...]");
  pf2::SlamOptions options;
  options.build_map = false;  // the report shows no map; the run stays short
  pf2::Settings settings = pf2::slamSettings(&options);
  for (int k = 3; k + 1 < argc; k += 2) {
    if (std::string(argv[k]) != "--set") throw pf2::Error(std::string("unknown option ") + argv[k]);
    settings.setAssignment(argv[k + 1]);
  }
  settings.validate();
  const pf2::TumSequence sequence(argv[1]);
  std::string detector;
  pf2::SlamSystem slam(options, pf2::createSlamDetector(options, argv[1], &detector));
  for (size_t i = 0; i < sequence.size(); ++i) slam.process(sequence.frame(i));
  const pf2::SlamResult result = slam.finish();
  const pf2::Trajectory ground_truth = sequence.groundTruth();

  pf2::RunReportInput input;
  // The folder's name, not its path: the page may be shared.
  std::string folder = argv[1];
  while (folder.size() > 1 && folder.back() == '/') folder.pop_back();
  folder = folder.substr(folder.find_last_of('/') + 1);
  input.title = "TUM folder " + folder;
  for (const std::string& key : settings.keys()) input.settings.emplace_back(key, settings.value(key));
  input.result = &result;
  input.stages = &slam.stats();
  if (!ground_truth.empty()) input.ground_truth = &ground_truth;
  pf2::writeRunReport(argv[2], input);
  std::printf("%s: %d frames, detector %s\n", argv[2], result.summary.frames, detector.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "pf2_report_demo: %s\n", error.what());
    return 1;
  }
}
