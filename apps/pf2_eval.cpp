// pf2_eval: absolute trajectory error and relative pose error of an estimate against ground truth,
// as the TUM RGB-D benchmark defines them.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "pf2/core/app_settings.h"
#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/core/settings.h"
#include "pf2/eval/trajectory_metrics.h"
#include "pf2/eval/trajectory_plot.h"
#include "pf2/io/trajectory_io.h"

namespace {

const char* kUsage =
    "Usage: pf2_eval GROUNDTRUTH ESTIMATE [options]\n"
    "Absolute trajectory error (ATE) of ESTIMATE against GROUNDTRUTH, both TUM trajectory files\n"
    "(timestamp tx ty tz qx qy qz qw), aligned in closed form (Horn/Umeyama) as the TUM benchmark does.\n"
    "\n"
    "Options (--max-diff, --scale, --delta, --delta-frames and --gt-format are settings, see --settings):\n"
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
    "  -h, --help         this text\n";
const char* kExitStatus = "Exit status: 0 on success, 1 on bad input (the error line names the file and line).\n";

// pf2_eval's settings (eval.*), declared once: --config, --set and the options below read them.
struct EvalSettings {
  pf2::AteOptions ate;
  pf2::RpeOptions rpe;
  std::string gt_format = "tum";
};

pf2::Settings declareEvalSettings(EvalSettings* e) {
  pf2::Settings s;
  s.number("eval.max_time_difference", &e->ate.max_time_difference, 0.0, 1.0, "s",
           "largest timestamp difference of an associated estimate and ground-truth pose");
  s.boolean("eval.estimate_scale", &e->ate.estimate_scale, "also estimate a scale in the alignment (monocular)");
  s.number("eval.rpe_delta", &e->rpe.delta, 1e-3, 1e6, "s or frames",
           "distance of the two poses of an RPE pair, in eval.rpe_delta_unit");
  s.custom(
      "eval.rpe_delta_unit",
      [e](const std::string& text) {
        if (text != "s" && text != "frames") throw pf2::Error("expected s or frames");
        e->rpe.unit = text == "s" ? pf2::RpeOptions::DeltaUnit::kSeconds : pf2::RpeOptions::DeltaUnit::kFrames;
      },
      [e] { return std::string(e->rpe.unit == pf2::RpeOptions::DeltaUnit::kFrames ? "frames" : "s"); },
      "s, frames", "unit of eval.rpe_delta");
  s.choice("eval.gt_format", &e->gt_format, {"tum", "bonn"},
           "what GROUNDTRUTH holds: camera poses (tum) or Bonn RGB-D Dynamic marker poses (bonn)");
  return s;
}

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  EvalSettings eval;
  pf2::Settings settings = declareEvalSettings(&eval);
  if (pf2::answeredHelpOrSettings(&cli, std::string(kUsage) + pf2::kSettingsUsage + kExitStatus, settings)) return 0;
  const bool with_rpe = cli.flag("--rpe");
  const bool as_json = cli.flag("--json");
  // --delta-frames N is a delta of N frames: the unit first, then the number.
  if (cli.has("--delta-frames")) settings.set("eval.rpe_delta_unit", "frames");
  pf2::readCommandLineSettings(&cli, &settings,
                               {{"--max-diff", "eval.max_time_difference"},
                                {"--scale", "eval.estimate_scale", "true"},
                                {"--delta", "eval.rpe_delta"},
                                {"--delta-frames", "eval.rpe_delta"},
                                {"--gt-format", "eval.gt_format"}});
  if (eval.rpe.unit == pf2::RpeOptions::DeltaUnit::kFrames && eval.rpe.delta != std::floor(eval.rpe.delta)) {
    throw pf2::Error("setting eval.rpe_delta = " + settings.value("eval.rpe_delta") +
                     ": a delta in frames must be a whole number");
  }
  eval.rpe.max_time_difference = eval.ate.max_time_difference;
  const pf2::AteOptions& ate_options = eval.ate;
  const pf2::RpeOptions& rpe_options = eval.rpe;
  const pf2::TrajectoryFormat gt_format = pf2::parseTrajectoryFormat(eval.gt_format, "eval.gt_format");
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

  // An alignment needs two poses on each side: a file with one is named, not left to the metric.
  if (ground_truth.size() < 2) throw pf2::fileError(files[0], "one pose only; the alignment needs at least 2");
  if (estimate.size() < 2) throw pf2::fileError(files[1], "one pose only; the alignment needs at least 2");
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
