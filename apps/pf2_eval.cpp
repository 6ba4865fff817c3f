// pf2_eval: absolute trajectory error and relative pose error of an estimate against ground truth,
// as the TUM RGB-D benchmark defines them.
#include <cstdio>
#include <iostream>
#include <string>

#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/eval/trajectory_metrics.h"
#include "pf2/eval/trajectory_plot.h"
#include "pf2/io/trajectory_io.h"

namespace {

const char* kUsage =
    "Usage: pf2_eval GROUNDTRUTH ESTIMATE [options]\n"
    "Absolute trajectory error (ATE) of ESTIMATE against GROUNDTRUTH, both TUM trajectory files\n"
    "(timestamp tx ty tz qx qy qz qw), aligned in closed form (Horn/Umeyama) as the TUM benchmark does.\n"
    "\n"
    "Options:\n"
    "  --rpe              also compute the relative pose error (all pairs at the given delta)\n"
    "  --delta D          RPE delta in seconds (default 1.0)\n"
    "  --delta-frames N   RPE delta in frames instead of seconds\n"
    "  --scale            also estimate a scale in the alignment (monocular estimates)\n"
    "  --max-diff S       largest timestamp difference for association, seconds (default 0.02)\n"
    "  --gt-format F      what GROUNDTRUTH holds: tum (camera poses, default) or bonn (the Bonn\n"
    "                     RGB-D Dynamic Dataset's marker poses, converted to camera poses)\n"
    "  --json             print one JSON object as the last line (ate_rmse, ate_mean, ate_median,\n"
    "                     ate_std, ate_min, ate_max, pairs, scale, and rpe_* with --rpe)\n"
    "  --plot FILE        top view of both trajectories with the error segments (.png or .svg)\n"
    "  -h, --help         this text\n"
    "Exit status: 0 on success, 1 on bad input (the error line names the file and line).\n";

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  if (cli.helpRequested()) {
    std::cout << kUsage;
    return 0;
  }
  const bool with_rpe = cli.flag("--rpe");
  const bool as_json = cli.flag("--json");
  pf2::AteOptions ate_options;
  ate_options.estimate_scale = cli.flag("--scale");
  ate_options.max_time_difference = cli.number("--max-diff", 0.02);
  pf2::RpeOptions rpe_options;
  rpe_options.max_time_difference = ate_options.max_time_difference;
  rpe_options.delta = cli.number("--delta", 1.0);
  const int delta_frames = cli.integer("--delta-frames", 0);
  if (delta_frames > 0) {
    rpe_options.delta = delta_frames;
    rpe_options.unit = pf2::RpeOptions::DeltaUnit::kFrames;
  }
  const pf2::TrajectoryFormat gt_format =
      pf2::parseTrajectoryFormat(cli.value("--gt-format", "tum"), "--gt-format");
  const auto plot_path = cli.value("--plot");
  const auto files = cli.positionals();
  if (files.size() != 2) {
    throw pf2::Error("expected GROUNDTRUTH and ESTIMATE, got " + std::to_string(files.size()) +
                     " file argument(s) (see -h)");
  }
  const pf2::Trajectory ground_truth = pf2::readTrajectory(files[0], gt_format);
  if (ground_truth.empty()) throw pf2::fileError(files[0], "no poses in file");
  const pf2::Trajectory estimate = pf2::readTrajectory(files[1]);
  if (estimate.empty()) throw pf2::fileError(files[1], "no poses in file");

  const pf2::AteResult ate = pf2::computeAte(ground_truth, estimate, ate_options);
  pf2::RpeResult rpe;
  if (with_rpe) rpe = pf2::computeRpe(ground_truth, estimate, rpe_options);
  if (plot_path) pf2::plotTrajectories(ate, *plot_path);

  const pf2::ErrorStatistics& a = ate.translation;
  std::printf("ate.pairs   %d\n", a.count);
  std::printf("ate.rmse    %.6f m\nate.mean    %.6f m\nate.median  %.6f m\nate.std     %.6f m\n"
              "ate.min     %.6f m\nate.max     %.6f m\n",
              a.rmse, a.mean, a.median, a.std, a.min, a.max);
  if (ate_options.estimate_scale) std::printf("ate.scale   %.6f\n", ate.scale);
  if (with_rpe) {
    const char* unit = rpe_options.unit == pf2::RpeOptions::DeltaUnit::kFrames ? "frames" : "s";
    std::printf("rpe.delta   %g %s\nrpe.pairs   %d\n", rpe_options.delta, unit, rpe.translation.count);
    std::printf("rpe.trans.rmse  %.6f m\nrpe.trans.mean  %.6f m\nrpe.trans.max   %.6f m\n",
                rpe.translation.rmse, rpe.translation.mean, rpe.translation.max);
    std::printf("rpe.rot.rmse    %.6f deg\nrpe.rot.mean    %.6f deg\nrpe.rot.max     %.6f deg\n",
                rpe.rotation.rmse, rpe.rotation.mean, rpe.rotation.max);
  }
  if (as_json) {
    std::printf("{\"ate_rmse\":%.9g,\"ate_mean\":%.9g,\"ate_median\":%.9g,\"ate_std\":%.9g,"
                "\"ate_min\":%.9g,\"ate_max\":%.9g,\"pairs\":%d,\"scale\":%.9g",
                a.rmse, a.mean, a.median, a.std, a.min, a.max, a.count, ate.scale);
    if (with_rpe) {
      std::printf(",\"rpe_pairs\":%d,\"rpe_trans_rmse\":%.9g,\"rpe_trans_mean\":%.9g,"
                  "\"rpe_trans_max\":%.9g,\"rpe_rot_rmse_deg\":%.9g,\"rpe_rot_mean_deg\":%.9g,"
                  "\"rpe_rot_max_deg\":%.9g",
                  rpe.translation.count, rpe.translation.rmse, rpe.translation.mean,
                  rpe.translation.max, rpe.rotation.rmse, rpe.rotation.mean, rpe.rotation.max);
    }
    std::printf("}\n");
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_eval", run, argc, argv); }
