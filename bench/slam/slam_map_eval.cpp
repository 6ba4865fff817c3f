// Map accuracy of a pf2_slam run on a pf2_synth sequence: the map (estimated poses, world = the
// first tracked camera) is moved into the ground truth's frame by the first tracked frame's
// ground-truth pose (a trajectory alignment would be undefined for a still or purely rotating
// camera, and this way drift counts against the map), then scored against gt/static_scene.ply: accuracy of the map vertices, ghosts
// (vertices > 3 cm from any static surface: people fused into the map) and completeness of the
// static surface the camera saw (samples observed by every 10th ground-truth depth frame).
//
// "Seen" is a sample that is the first static surface on the ray of a pixel where the sensor
// measured a depth within range and no person stands in front (the ground-truth mesh rendered at
// the ground-truth pose, people masked by gt/masks): the rule pf2_surface_map_quality uses with its
// exact depth. --noisy-depth-seen selects the older rule, a sample within 2 cm of the sensor's
// noisy depth at its pixel: beyond ~2.5 m the Kinect model's noise and disparity steps reach that
// tolerance, so surfaces a few cm behind the visible one (undersides and back faces of boards)
// pass in some frames although no ray reached them; it over-counts what was seen.
//
//   pf2_slam_map_eval SEQUENCE_DIR RUN_DIR [--every K] [--max-depth M] [--noisy-depth-seen]
#include <cstdio>
#include <iostream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/eval/trajectory_metrics.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/io/tum_sequence.h"
#include "pf2/surface/map_evaluator.h"
#include "pf2/surface/triangle_mesh.h"
#include "pf2/synth/rasterizer.h"

namespace {

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  if (cli.helpRequested()) {
    std::cout << "usage: pf2_slam_map_eval SEQUENCE_DIR RUN_DIR [--every K] [--max-depth M] [--noisy-depth-seen]\n"
                 "Scores RUN_DIR/map.ply (aligned by RUN_DIR/trajectory.txt) against\n"
                 "SEQUENCE_DIR/gt/static_scene.ply. Seen samples are the first static surface on the ray\n"
                 "of a pixel with depth in range and no person (needs SEQUENCE_DIR/gt/masks);\n"
                 "--noisy-depth-seen: any sample within 2 cm of the noisy depth (the older rule).\n";
    return 0;
  }
  const int every = cli.integer("--every", 10);
  // The map fuses depth up to the TSDF's max_depth (3.5 m by default): surface seen only from
  // farther away cannot be in it and is not counted as missed.
  const double max_depth = cli.number("--max-depth", 3.5);
  const bool visible_only = !cli.flag("--noisy-depth-seen");
  const auto args = cli.positionals();
  if (args.size() != 2) throw pf2::Error("expected SEQUENCE_DIR and RUN_DIR (see -h)");
  const std::string& sequence_dir = args[0];
  const std::string& run_dir = args[1];

  const pf2::TumSequence sequence(sequence_dir);
  const pf2::Trajectory ground_truth = sequence.groundTruth();
  const pf2::Trajectory estimate = pf2::readTrajectory(run_dir + "/trajectory.txt");
  if (estimate.empty()) throw pf2::fileError(run_dir + "/trajectory.txt", "no poses");
  Eigen::Isometry3d T_gt_first;
  if (!pf2::interpolateAt(ground_truth, estimate.front().timestamp, 0.1, &T_gt_first)) {
    throw pf2::Error("no ground truth at the first tracked frame");
  }
  const Eigen::Isometry3d T_gt_est = T_gt_first * estimate.front().T_w_c.inverse();
  const pf2::AteResult ate = pf2::computeAte(ground_truth, estimate);
  pf2::TriangleMesh map = pf2::loadMeshPly(run_dir + "/map.ply");
  for (auto& v : map.vertices) v = (T_gt_est * v.cast<double>()).cast<float>();
  const pf2::TriangleMesh truth = pf2::loadMeshPly(sequence_dir + "/gt/static_scene.ply");
  pf2::MapEvaluator evaluator(truth, pf2::MapEvaluator::Options());
  pf2::RenderMesh truth_render;
  truth_render.vertices = truth.vertices;
  truth_render.triangles = truth.triangles;
  truth_render.colors.assign(truth.vertices.size(), Eigen::Vector3f::Constant(0.5f));
  truth_render.cull_back_faces = false;  // the PLY's winding is not relied on: nearest surface wins
  const pf2::Rasterizer rasterizer;
  for (size_t i = 0; i < sequence.size(); i += std::max(1, every)) {
    Eigen::Isometry3d T_w_c;
    if (!pf2::interpolateAt(ground_truth, sequence.timestamp(i), 0.02, &T_w_c)) continue;
    pf2::Frame frame = sequence.frame(i);
    frame.depth.setTo(0.0f, frame.depth > max_depth);
    if (visible_only) {
      // Exact static depth where the sensor measured in range and no person stands in front.
      const std::string depth_file = sequence.files(i).depth.file;
      const std::string mask_path =
          sequence_dir + "/gt/masks/" + depth_file.substr(depth_file.find_last_of('/') + 1);
      const cv::Mat mask = cv::imread(mask_path, cv::IMREAD_UNCHANGED);
      if (mask.empty() || mask.size() != frame.depth.size()) {
        throw pf2::fileError(mask_path, "no person mask of the depth's size");
      }
      pf2::RenderedImages rendered;
      rasterizer.render({&truth_render}, {}, frame.intrinsics, T_w_c, &rendered);
      rendered.depth.setTo(0.0f, (frame.depth <= 0.0f) | (mask > 0));
      frame.depth = rendered.depth;
    }
    evaluator.markSeen(frame.depth, frame.intrinsics, T_w_c);
  }
  const pf2::MapQuality q = evaluator.evaluate(map);
  std::printf("trajectory ATE %.4f m; map vertices %zu\n", ate.translation.rmse, q.map_vertices);
  std::printf("accuracy mean %.4f m, median %.4f m, p90 %.4f m\n", q.mean, q.median, q.p90);
  std::printf("ghost vertices (> 3 cm) %zu (%.2f %%)\n", q.ghost_vertices,
              100.0 * q.ghost_vertices / std::max<size_t>(1, q.map_vertices));
  std::printf("completeness (2 cm) %.1f %% of %zu %s samples\n", 100.0 * q.completeness, q.seen_samples,
              visible_only ? "seen and visible" : "seen");
  std::printf("%s", pf2::completenessBreakdown(q).c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_slam_map_eval", run, argc, argv); }
