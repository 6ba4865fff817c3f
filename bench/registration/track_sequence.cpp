// pf2_track_sequence: runs the registration Tracker over a TUM-layout folder and reports ATE
// against its groundtruth.txt, the tracking rate (image decoding excluded), lost frames,
// keyframes and loop closures. The measurement tool behind docs/BENCHMARKS.md (registration).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/core/pose.h"
#include "pf2/core/stage_timer.h"
#include "pf2/eval/trajectory_metrics.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/io/tum_sequence.h"
#include "pf2/registration/tracker.h"

namespace {

const char* kUsage =
    "usage: pf2_track_sequence FOLDER [--out TRAJ.txt] [--frames N] [--sync] [--features-every-frame]\n"
    "                          [--finest-level L] [--points N] [--no-photometric] [--masks DIR]\n"
    "                          [--mask-mode remove|keep] [--distortion auto|none|fr1|fr2]\n"
    "                          [--depth-sigma M] [--intensity-sigma I] [--kf-rotation RAD]\n"
    "                          [--kf-translation M] [--convergence STEP] [--iterations-coarse N]\n"
    "                          [--iterations-fine N] [--no-loops] [--loop-gap K] [--json] [--verbose]\n"
    "  FOLDER   TUM layout (rgb.txt, depth.txt, rgb/, depth/, groundtruth.txt)\n"
    "  --out    write the estimated trajectory after loop closing (tracked frames only; lost\n"
    "           frames are left out)\n"
    "  --frames use only the first N frames\n"
    "  --sync   run the back-end inside track() instead of its own thread\n"
    "  --masks  folder of person label images named like the depth images (pf2_synth's gt/masks:\n"
    "           0 = static, > 0 = person)\n"
    "  --mask-mode remove (default): cut the masked pixels out of depth and colour;\n"
    "              keep: read the masks but do not use them (people stay in the frames)\n"
    "  --distortion lens model to undistort with; auto = TUM fr1/fr2 values when the intrinsics\n"
    "           are the fr1/fr2 preset, else none\n"
    "  --depth-sigma, --intensity-sigma, --kf-rotation, --kf-translation, --convergence,\n"
    "  --iterations-coarse, --iterations-fine: override the defaults (RgbdOdometry::Options)\n"
    "  --no-loops  no loop closing (pose graph of odometry edges only)\n"
    "  --loop-gap  keyframes between the two ends of a loop (default 10)\n"
    "  --json   last line of output: one JSON object with the figures\n"
    "  --verbose one line per frame: status, keyframe, sparse and dense quality, time\n";

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  if (cli.helpRequested()) {
    std::fputs(kUsage, stdout);
    return 0;
  }
  const std::string out = cli.value("--out", "");
  const int max_frames = cli.integer("--frames", 0);
  pf2::Tracker::Options options;
  options.asynchronous_backend = !cli.flag("--sync");
  options.odometry.features_every_frame = cli.flag("--features-every-frame");
  options.odometry.finest_level = cli.integer("--finest-level", options.odometry.finest_level);
  options.odometry.max_points_per_level = cli.integer("--points", options.odometry.max_points_per_level);
  if (cli.flag("--no-photometric")) options.odometry.photometric_weight = 0.0;
  const std::string mask_dir = cli.value("--masks", "");
  const std::string mask_mode = cli.value("--mask-mode", "remove");
  if (mask_mode != "remove" && mask_mode != "keep") throw pf2::Error("--mask-mode: remove or keep");
  const std::string distortion = cli.value("--distortion", "auto");
  if (distortion != "auto" && distortion != "none" && distortion != "fr1" && distortion != "fr2")
    throw pf2::Error("--distortion: auto, none, fr1 or fr2");
  options.odometry.depth_sigma = cli.number("--depth-sigma", options.odometry.depth_sigma);
  options.odometry.intensity_sigma = cli.number("--intensity-sigma", options.odometry.intensity_sigma);
  options.keyframes.max_rotation = cli.number("--kf-rotation", options.keyframes.max_rotation);
  options.keyframes.max_translation = cli.number("--kf-translation", options.keyframes.max_translation);
  options.odometry.convergence_step = cli.number("--convergence", options.odometry.convergence_step);
  options.odometry.iterations_coarse = cli.integer("--iterations-coarse", options.odometry.iterations_coarse);
  options.odometry.iterations_fine = cli.integer("--iterations-fine", options.odometry.iterations_fine);
  if (cli.flag("--no-loops")) options.backend.max_candidates = 0;
  options.backend.min_loop_gap = cli.integer("--loop-gap", options.backend.min_loop_gap);
  options.backend.loop_translation_sigma = cli.number("--loop-sigma-t", options.backend.loop_translation_sigma);
  options.backend.loop_rotation_sigma = cli.number("--loop-sigma-r", options.backend.loop_rotation_sigma);
  options.backend.min_loop_inlier_ratio = cli.number("--loop-inliers", options.backend.min_loop_inlier_ratio);
  const bool json = cli.flag("--json");
  const bool verbose = cli.flag("--verbose");
  const std::vector<std::string> positionals = cli.positionals();
  if (positionals.size() != 1) throw pf2::Error(std::string("expected one folder\n") + kUsage);

  const pf2::TumSequence sequence(positionals[0]);
  // auto: the TUM camera named by the folder (its intrinsics preset says which).
  const double fx = sequence.intrinsics().fx;
  const std::string camera = distortion != "auto" ? distortion
                             : fx == pf2::CameraIntrinsics::tumFreiburg1().fx ? "fr1"
                             : fx == pf2::CameraIntrinsics::tumFreiburg2().fx ? "fr2" : "none";
  if (camera == "fr1") options.odometry.distortion = pf2::kTumFreiburg1Distortion;
  if (camera == "fr2") options.odometry.distortion = pf2::kTumFreiburg2Distortion;
  const size_t n = max_frames > 0 ? std::min<size_t>(max_frames, sequence.size()) : sequence.size();
  pf2::Tracker tracker(options);
  pf2::Trajectory estimate;
  std::vector<std::pair<int, Eigen::Isometry3d>> anchored;  // (keyframe, T_k_c) per tracked frame
  std::vector<double> frame_ms, frame_cpu_ms;
  int lost = 0, relocalised = 0;
  for (size_t i = 0; i < n; ++i) {
    const pf2::Frame frame = sequence.frame(i);
    cv::Mat mask;
    if (!mask_dir.empty()) {
      // Label images named like the depth images: 0 = static, k > 0 = person k (any depth).
      const std::string& depth_file = sequence.files(i).depth.file;
      const std::string file = mask_dir + "/" + depth_file.substr(depth_file.rfind('/') + 1);
      const cv::Mat labels = cv::imread(file, cv::IMREAD_UNCHANGED);
      if (labels.empty() || labels.channels() != 1 || labels.size() != frame.depth.size())
        throw pf2::fileError(file, "cannot read person mask (single channel, frame size)");
      mask = labels > 0;
    }
    pf2::Frame input = frame;
    if (!mask.empty() && mask_mode == "remove") {
      input.depth = input.depth.clone();
      input.depth.setTo(0.0f, mask > 0);
    } else {
      mask = cv::Mat();
    }
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpu_start = std::clock();
    const pf2::TrackResult result = tracker.track(input, mask);
    frame_ms.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    // Process CPU time (all threads): a figure that does not depend on what else the machine runs.
    frame_cpu_ms.push_back(1000.0 * double(std::clock() - cpu_start) / CLOCKS_PER_SEC);
    if (verbose) {
      const pf2::OdometryResult& o = result.odometry;
      std::printf("%4zu %-11s kf %3d%s feat %d (%d/%d) dense inl %.2f n %d it %d rmse %.4f cond %.1e %.1f ms\n",
                  i, pf2::toString(result.status), result.keyframe_id,
                  result.keyframe_created ? "*" : " ", o.used_features, o.sparse.inliers,
                  o.sparse.matches, o.dense.inlier_ratio, o.dense.sampled_points, o.dense.iterations,
                  o.dense.geometric_rmse, o.dense.hessian_condition, frame_ms.back());
    }
    if (result.status == pf2::TrackStatus::kLost) {
      ++lost;
      continue;
    }
    if (result.status == pf2::TrackStatus::kRelocalised) ++relocalised;
    estimate.push_back({frame.timestamp, result.T_w_c});
    anchored.emplace_back(result.keyframe_id, result.T_k_c);
  }
  tracker.finish();

  // Live: the poses track() returned. Corrected: each frame re-anchored on its keyframe's final
  // (pose-graph corrected) pose, what a mapper re-integrating keyframes would end up with.
  pf2::Trajectory corrected = estimate;
  for (size_t i = 0; i < corrected.size(); ++i)
    corrected[i].T_w_c = tracker.keyframes().pose(anchored[i].first) * anchored[i].second;
  if (verbose && sequence.hasGroundTruth()) {
    // Each accepted loop edge against the ground-truth relative pose of its two keyframes.
    for (const auto& loop : tracker.backend().loopClosures()) {
      Eigen::Isometry3d T_w_a, T_w_b;
      if (!pf2::interpolateAt(sequence.groundTruth(), tracker.keyframes().keyframe(loop.from)->timestamp, 0.1, &T_w_a) ||
          !pf2::interpolateAt(sequence.groundTruth(), tracker.keyframes().keyframe(loop.to)->timestamp, 0.1, &T_w_b))
        continue;
      const Eigen::Isometry3d error = (T_w_a.inverse() * T_w_b).inverse() * loop.T_from_to;
      std::printf("loop %3d -> %3d inlier ratio %.2f error %.4f m %.3f deg\n", loop.from, loop.to,
                  loop.inlier_ratio, error.translation().norm(),
                  pf2::rotationAngle(error.rotation()) * 180.0 / M_PI);
    }
  }
  const double median_ms = pf2::percentile(frame_ms, 50.0);
  const int keyframes = static_cast<int>(tracker.keyframes().size());
  const int loops = static_cast<int>(tracker.backend().loopClosures().size());
  if (!out.empty()) pf2::writeTrajectory(out, corrected);
  double ate = -1.0, ate_corrected = -1.0;
  if (sequence.hasGroundTruth() && estimate.size() >= 3) {
    ate = pf2::computeAte(sequence.groundTruth(), estimate).translation.rmse;
    ate_corrected = pf2::computeAte(sequence.groundTruth(), corrected).translation.rmse;
  }
  std::printf("frames %zu tracked %zu lost %d relocalised %d keyframes %d loops %d\n", n,
              estimate.size(), lost, relocalised, keyframes, loops);
  const double median_cpu_ms = pf2::percentile(frame_cpu_ms, 50.0);
  std::printf("ATE RMSE live %.4f m, after loop closing %.4f m; track median %.2f ms (%.1f frames/s), "
              "p90 %.2f ms; CPU median %.2f ms/frame\n", ate, ate_corrected, median_ms,
              1000.0 / median_ms, pf2::percentile(frame_ms, 90.0), median_cpu_ms);
  for (const std::string& stage : tracker.stats().stages()) {
    const pf2::StageSummary s = tracker.stats().summary(stage);
    std::printf("  %-11s count %5d median %7.2f ms mean %7.2f ms max %7.2f ms\n", stage.c_str(),
                s.count, s.median_ms, s.mean_ms, s.max_ms);
  }
  if (json)
    std::printf("{\"frames\":%zu,\"tracked\":%zu,\"lost\":%d,\"relocalised\":%d,\"keyframes\":%d,"
                "\"loops\":%d,\"ate_rmse\":%.6f,\"ate_rmse_corrected\":%.6f,\"median_ms\":%.3f,"
                "\"fps\":%.2f,\"median_cpu_ms\":%.3f}\n",
                n, estimate.size(), lost, relocalised, keyframes, loops, ate, ate_corrected, median_ms,
                1000.0 / median_ms, median_cpu_ms);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_track_sequence", run, argc, argv); }
