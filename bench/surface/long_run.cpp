// Memory of the Mapper over a long run: a camera walking laps through a 16 x 3 x 16 m hall with
// pillars (analytic depth, 640x480), every k-th frame fused as a keyframe (as a SLAM front end
// hands them over). Prints the peak resident set size and the map's size every `--report` frames,
// with the bounds on (default) or off.
//
//   pf2_surface_long_run [--frames 10000] [--every 5] [--unbounded] [--keep-radius 5]
//                        [--stored-keyframes 200] [--report 1000]
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "analytic_scene.h"
#include "pf2/core/command_line.h"
#include "pf2/surface/mapper.h"

namespace {

double peakRssMegabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux reports kilobytes
}

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  if (cli.helpRequested()) {
    std::printf(
        "usage: pf2_surface_long_run [--frames N] [--every K] [--unbounded] [--keep-radius M]\n"
        "                            [--stored-keyframes N] [--report N]\n"
        "A camera walks N frames through a hall; every K-th frame (analytic 640x480 depth and colour)\n"
        "is fused as a keyframe. Prints the map's size and the peak memory.\n");
    return 0;
  }
  const int frames = cli.integer("--frames", 10000);
  const int every = std::max(1, cli.integer("--every", 5));
  const bool unbounded = cli.flag("--unbounded");
  const double keep_radius = cli.number("--keep-radius", 5.0);
  const int stored = cli.integer("--stored-keyframes", 200);
  const int report = cli.integer("--report", 1000);
  cli.positionals();

  pf2::test::AnalyticScene hall;
  hall.has_room = true;
  hall.room = {Eigen::Vector3d(-8, -2.5, -8), Eigen::Vector3d(8, 0.5, 8)};  // floor at y = 0.5 (y down)
  for (int x = -1; x <= 1; x += 2) {
    for (int z = -1; z <= 1; z += 2) {
      hall.boxes.push_back({Eigen::Vector3d(4.0 * x - 0.3, -2.5, 4.0 * z - 0.3), Eigen::Vector3d(4.0 * x + 0.3, 0.5, 4.0 * z + 0.3)});
    }
  }
  hall.spheres.push_back({Eigen::Vector3d(0, -0.5, 0), 0.8});

  pf2::Mapper::Options options;
  options.occupancy.pixel_stride = 8;
  if (!unbounded) {
    options.keep_radius = keep_radius;
    options.max_stored_keyframes = stored;
  }
  pf2::Mapper mapper(options);
  const pf2::CameraIntrinsics K;
  std::printf("# frames %d, keyframe every %d, %s\n", frames, every,
              unbounded ? "unbounded" : ("keep_radius " + std::to_string(keep_radius) + " m, stored keyframes " +
                                         std::to_string(stored)).c_str());
  std::printf("%8s %10s %10s %12s %12s %12s %10s\n", "frame", "stored_kf", "blocks", "tsdf_MB", "mapper_MB", "peak_rss_MB", "s");
  const auto start = std::chrono::steady_clock::now();
  cv::Mat depth, bgr;
  for (int i = 0; i < frames; ++i) {
    // An ellipse of 6 x 5 m half axes, 1 cm per frame, looking ahead and a little outward.
    const double t = i * 0.01 / 5.5;
    const Eigen::Vector3d p_w(6.0 * std::cos(t), -1.0 + 0.2 * std::sin(3 * t), 5.0 * std::sin(t));
    const Eigen::Vector3d ahead(-6.0 * std::sin(t), 0.1, 5.0 * std::cos(t));
    const Eigen::Vector3d outward(std::cos(t), 0.0, std::sin(t));
    const Eigen::Isometry3d T_w_c = pf2::test::lookAt(p_w, p_w + ahead.normalized() + 0.6 * std::sin(0.7 * t) * outward);
    if (i % every == 0) {
      hall.render(K, T_w_c, &depth, &bgr);
      mapper.addKeyframe(i, depth, bgr, K, T_w_c);
    }
    if ((i + 1) % report == 0 || i + 1 == frames) {
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      std::printf("%8d %10zu %10zu %12.1f %12.1f %12.1f %10.0f\n", i + 1, mapper.keyframeCount(),
                  mapper.tsdf().blockCount(), mapper.tsdf().memoryBytes() / 1e6, mapper.memoryBytes() / 1e6,
                  peakRssMegabytes(), seconds);
      std::fflush(stdout);
    }
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_surface_long_run", run, argc, argv); }
