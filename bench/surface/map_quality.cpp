// Map quality on a synthetic sequence (pf2_synthesis): the static map fused from every k-th frame
// at the ground-truth poses, with the people cut out of the depth by the ground-truth masks (or
// left in with --keep-people), scored against the scene's ground-truth static mesh: accuracy of
// the map's vertices, ghosts (vertices > 3 cm from any static surface), completeness of the seen
// static surface; plus fusion and meshing times.
//
//   pf2_surface_map_quality [--frames 300] [--people 3] [--motion xyz] [--seed 1] [--every 5]
//                           [--keep-people] [--dilate PX] [--no-noise] [--voxel M] [--out DIR]
#include <chrono>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/surface/map_evaluator.h"
#include "pf2/surface/mapper.h"
#include "pf2/synth/synthetic_sequence.h"

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  if (cli.helpRequested()) {
    std::printf(
        "usage: pf2_surface_map_quality [--frames N] [--people N] [--motion NAME] [--seed N] [--every K]\n"
        "                               [--keep-people] [--dilate PX] [--no-noise] [--voxel M] [--max-depth M]\n"
        "                               [--out DIR]\n"
        "Fuses every K-th frame of a synthetic sequence at the ground-truth poses, people removed by the\n"
        "ground-truth masks (dilated by PX pixels), and scores the map against the static scene mesh.\n");
    return 0;
  }
  pf2::SyntheticSequence::Options sequence_options;
  sequence_options.frames = cli.integer("--frames", 300);
  sequence_options.people = cli.integer("--people", 3);
  sequence_options.camera = pf2::cameraMotionFromName(cli.value("--motion", "xyz"));
  sequence_options.seed = static_cast<std::uint64_t>(cli.integer("--seed", 1));
  const int every = std::max(1, cli.integer("--every", 5));
  const bool keep_people = cli.flag("--keep-people");
  const int dilate = cli.integer("--dilate", 0);
  sequence_options.sensor.noise = !cli.flag("--no-noise");
  pf2::Mapper::Options mapper_options;
  mapper_options.tsdf.voxel_size = cli.number("--voxel", 0.01);
  mapper_options.tsdf.max_depth = cli.number("--max-depth", mapper_options.tsdf.max_depth);
  mapper_options.occupancy.max_range = mapper_options.tsdf.max_depth;
  const std::string out = cli.value("--out", "");
  cli.positionals();

  const pf2::SyntheticSequence sequence(sequence_options);
  const pf2::RenderMesh& scene_mesh = sequence.scene().mesh();
  pf2::TriangleMesh truth_mesh;
  truth_mesh.vertices = scene_mesh.vertices;
  truth_mesh.triangles = scene_mesh.triangles;
  pf2::MapEvaluator evaluator(truth_mesh, pf2::MapEvaluator::Options());
  pf2::Mapper mapper(mapper_options);

  double fuse_seconds = 0.0;
  int keyframes = 0;
  long removed_pixels = 0;
  for (size_t i = 0; i < sequence.size(); i += every) {
    pf2::FrameGroundTruth truth;
    const pf2::Frame frame = sequence.frame(i, &truth);
    cv::Mat people = truth.labels > 0;
    if (dilate > 0) cv::dilate(people, people, cv::Mat(), cv::Point(-1, -1), dilate);
    cv::Mat depth = frame.depth.clone();
    if (!keep_people) {
      removed_pixels += cv::countNonZero(people & (depth > 0));
      depth.setTo(0.f, people);
    }
    // Seen static surface: the exact depth where the sensor measured within the map's depth range
    // and no person stands in front of it.
    cv::Mat static_exact = truth.exact_depth.clone();
    static_exact.setTo(0.f, (truth.labels > 0) | (frame.depth < mapper_options.tsdf.min_depth) |
                                (frame.depth > mapper_options.tsdf.max_depth));
    evaluator.markSeen(static_exact, frame.intrinsics, truth.T_w_c);
    const auto start = std::chrono::steady_clock::now();
    mapper.addKeyframe(static_cast<int>(i), depth, frame.rgb, frame.intrinsics, truth.T_w_c);
    fuse_seconds += secondsSince(start);
    ++keyframes;
  }
  auto start = std::chrono::steady_clock::now();
  const pf2::TriangleMesh map = mapper.extractMesh();
  const double mesh_seconds = secondsSince(start);
  start = std::chrono::steady_clock::now();
  const pf2::MapQuality q = evaluator.evaluate(map);
  const double evaluate_seconds = secondsSince(start);
  if (!out.empty()) {
    pf2::Mapper::ExportOptions what;
    what.points_pcd = true;
    mapper.exportMap(out, what);
  }
  std::printf("sequence        %s, every %d-th frame (%d keyframes), people %s\n", sequence.description().c_str(),
              every, keyframes, keep_people ? "kept in the depth" : "removed by ground-truth masks");
  std::printf("removed pixels  %.1f per keyframe\n", keyframes ? static_cast<double>(removed_pixels) / keyframes : 0.0);
  std::printf("map             %zu vertices, %zu triangles, %zu blocks\n", map.vertices.size(), map.triangles.size(),
              mapper.tsdf().blockCount());
  std::printf("accuracy        mean %.2f mm, median %.2f mm, p90 %.2f mm, max %.2f mm (capped at %.0f mm)\n",
              1e3 * q.mean, 1e3 * q.median, 1e3 * q.p90, 1e3 * q.max, 1e3 * pf2::MapEvaluator::Options().max_distance);
  std::printf("ghosts          %zu vertices farther than 3 cm from the static scene (%.3f %%)\n", q.ghost_vertices,
              q.map_vertices ? 100.0 * q.ghost_vertices / q.map_vertices : 0.0);
  std::printf("completeness    %.2f %% of %zu seen ground-truth samples within 2 cm of the map\n",
              100.0 * q.completeness, q.seen_samples);
  std::printf("%s", pf2::completenessBreakdown(q).c_str());
  std::printf("time            fuse %.1f ms per keyframe (Mapper::addKeyframe, incl. OctoMap), mesh %.0f ms, "
              "evaluation %.1f s\n", keyframes ? 1e3 * fuse_seconds / keyframes : 0.0, 1e3 * mesh_seconds,
              evaluate_seconds);
  std::printf("{\"keyframes\":%d,\"vertices\":%zu,\"mean_m\":%.6f,\"median_m\":%.6f,\"p90_m\":%.6f,\"ghosts\":%zu,"
              "\"completeness\":%.5f,\"fuse_ms\":%.2f,\"mesh_ms\":%.1f}\n",
              keyframes, q.map_vertices, q.mean, q.median, q.p90, q.ghost_vertices, q.completeness,
              keyframes ? 1e3 * fuse_seconds / keyframes : 0.0, 1e3 * mesh_seconds);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_surface_map_quality", run, argc, argv); }
