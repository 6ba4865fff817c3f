// Writes the report of the sample run (sample_run.h) to a path: the input of the headless
// Chromium test and of the screenshot in docs/.
//
//   pf2_report_fixture OUT.html [--no-ground-truth] [--frames N]
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "sample_run.h"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: pf2_report_fixture OUT.html [--no-ground-truth] [--frames N]\n");
    return 2;
  }
  bool ground_truth = true;
  pf2::test::SampleOptions options;
  for (int k = 2; k < argc; ++k) {
    const std::string arg = argv[k];
    if (arg == "--no-ground-truth") {
      ground_truth = false;
    } else if (arg == "--frames" && k + 1 < argc) {
      options.frames = std::atoi(argv[++k]);
    } else {
      std::fprintf(stderr, "pf2_report_fixture: unknown option %s\n", arg.c_str());
      return 2;
    }
  }
  try {
    pf2::test::SampleRun run;
    pf2::test::makeSampleRun(options, &run);
    pf2::writeRunReport(argv[1], run.input(ground_truth));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "pf2_report_fixture: %s\n", error.what());
    return 1;
  }
  return 0;
}
