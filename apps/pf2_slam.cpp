// pf2_slam: dynamic RGB-D SLAM on a TUM-layout folder, or on the built-in synthetic sequence.
#include <sys/stat.h>

#include <cstdio>
#include <iostream>
#include <string>

#include "pf2/core/app_settings.h"
#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/core/settings.h"
#include "pf2/eval/trajectory_metrics.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/io/tum_sequence.h"
#include "pf2/io/tum_sequence_settings.h"
#include "pf2/registration/rgbd_odometry.h"
#include "pf2/slam/slam_system.h"
#include "pf2/synth/synth_settings.h"
#include "pf2/synth/synthetic_sequence.h"

namespace {

const char* kUsage =
    "Usage: pf2_slam [SEQUENCE_DIR] [-o OUT_DIR] [options]\n"
    "Removes people from every depth frame, tracks the camera on the rest and fuses a static map.\n"
    "Without SEQUENCE_DIR the built-in synthetic sequence (people walking in a textured room) is\n"
    "generated into OUT_DIR/synthetic, run, and evaluated against its ground truth.\n"
    "\n"
    "Outputs in OUT_DIR (default pf2_output): trajectory.txt (TUM format, one line per frame with a\n"
    "pose), stats.json (frames, lost frames, per-stage median/p90 ms, fps), map.ply, map.bt, map.ot,\n"
    "with a detector: humans.txt ('timestamp id x y z', each person's pelvis in the world frame of\n"
    "trajectory.txt), humans.json (each person's body per frame: pose, shape, joints) and scene.ply,\n"
    "scene.obj (the map with each person's body and track).\n"
    "\n"
    "Options:\n"
    "  -o DIR               output folder (created if needed)\n"
    "  --detector NAME      auto (default: learned when its models are installed, else hog),\n"
    "                       none (no person removal), gt (ground-truth oracle of pf2_synth folders),\n"
    "                       hog, file, yolo, selfie, movenet, learned\n"
    "  --eval GROUNDTRUTH   print ATE (and RPE over 1 s) of the trajectory at the end\n"
    "  --gt-format F        tum or bonn (GROUNDTRUTH holds Bonn RGB-D Dynamic marker poses); default\n"
    "                       bonn for a folder named rgbd_bonn_*, else tum\n"
    "  --config FILE        'key value' settings, one per line (docs/config.md lists the keys)\n"
    "  --set KEY=VALUE      one setting, after --config (repeatable); e.g. --set map.voxel_size=0.02\n"
    "  --settings           print every setting (key, default, unit, allowed values, meaning) and exit\n"
    "Each option below is a setting applied after --set: --frames N is --set run.max_frames=N.\n"
    "  --frames N           process only the first N frames\n"
    "  --no-map             track only; no TSDF/OctoMap\n"
    "  --pcd                also write map.pcd (the mesh vertices as coloured points)\n"
    "  --obj                also write map.obj (the mesh as Wavefront OBJ with vertex colours)\n"
    "  --masks              also write masks/<timestamp>.png per frame (255 = depth removed)\n"
    "  --no-bodies          no body fits: humans.txt from the eq. 2 centres, no humans.json/scene.*\n"
    "  --bodies-every N     scene.ply/.obj also show every N-th body along each track\n"
    "  --calibration FILE   camera calibration file (default: camera.txt in the folder or TUM preset)\n"
    "  --associations FILE  rgb/depth associations instead of matching rgb.txt and depth.txt\n"
    "  --depth-scale S      depth PNG units per metre (default 5000)\n"
    "  --distortion D       auto (TUM fr1/fr2 lens distortion for those presets), none, fr1, fr2\n"
    "  --quiet              no progress line\n"
    "Built-in sequence:\n"
    "  --synth-frames N     frames (default 300)   --synth-people K  people 0..5 (default 3)\n"
    "  --synth-camera M     static|xyz|halfsphere|rpy|loop (default xyz)   --seed S (default 1)\n"
    "  -h, --help           this text\n";

bool samePinhole(const pf2::CameraIntrinsics& a, const pf2::CameraIntrinsics& b) {
  return a.fx == b.fx && a.fy == b.fy && a.cx == b.cx && a.cy == b.cy;
}

// The TUM benchmark publishes lens distortion for its fr1 and fr2 Kinects and does not rectify the
// images; "auto" applies it when the sequence uses one of those presets.
std::vector<double> lensDistortion(const std::string& name, const pf2::CameraIntrinsics& K) {
  if (name == "fr1" || (name == "auto" && samePinhole(K, pf2::CameraIntrinsics::tumFreiburg1()))) {
    return pf2::kTumFreiburg1Distortion;
  }
  if (name == "fr2" || (name == "auto" && samePinhole(K, pf2::CameraIntrinsics::tumFreiburg2()))) {
    return pf2::kTumFreiburg2Distortion;
  }
  if (name == "auto" || name == "none") return {};
  throw pf2::Error("option --distortion: expected auto, none, fr1 or fr2, got '" + name + "'");
}

bool exists(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0;
}

// The run's figures: frames and their status, keyframes, speed per stage.
void printSummary(const std::string& sequence, const pf2::SlamRunSummary& s, const pf2::StageStats& stats) {
  std::printf("sequence    %s\n", sequence.c_str());
  std::printf("detector    %s\n", s.detector.c_str());
  std::printf("frames      %d (posed %d: bridged %d, relocalised %d; lost %d)\n", s.frames, s.tracked,
              s.bridged, s.relocalised, s.lost);
  std::printf("keyframes   %d (local edges %d, loop closures %d)\n", s.keyframes, s.local_edges, s.loop_closures);
  std::printf("fps         %.1f end to end (%.1f s)\n", s.fps, s.seconds);
  for (const std::string& stage : stats.stages()) {
    const pf2::StageSummary t = stats.summary(stage);
    std::printf("  %-11s median %7.2f ms   p90 %7.2f ms   (%d calls)\n", stage.c_str(), t.median_ms,
                t.p90_ms, t.count);
  }
}

// ATE (and RPE over 1 s) of the run's trajectory against the ground truth.
void printAccuracy(const pf2::Trajectory& ground_truth, const pf2::Trajectory& trajectory) {
  const pf2::AteResult ate = pf2::computeAte(ground_truth, trajectory);
  std::printf("ate.rmse    %.4f m  (mean %.4f, max %.4f, %d poses)\n", ate.translation.rmse,
              ate.translation.mean, ate.translation.max, ate.translation.count);
  try {
    const pf2::RpeResult rpe = pf2::computeRpe(ground_truth, trajectory, pf2::RpeOptions());
    std::printf("rpe.rmse    %.4f m, %.3f deg per second\n", rpe.translation.rmse, rpe.rotation.rmse);
  } catch (const pf2::Error& e) {
    // Too few poses one second apart (a short or mostly lost run): the ATE above still stands.
    std::printf("rpe.rmse    unavailable (%s)\n", e.what());
  }
}

void printOutputs(const std::string& out_dir, const pf2::SlamOptions& options, const std::string& detector) {
  std::string files = "trajectory.txt, stats.json";
  if (options.build_map) {
    files += ", map.ply";
    if (options.mapper.build_occupancy) files += ", map.bt, map.ot";
    if (options.map_files.points_pcd) files += ", map.pcd";
    if (options.map_files.mesh_obj) files += ", map.obj";
  }
  const bool people = detector != "none";
  if (options.track_humans && people) files += ", humans.txt";
  if (options.track_humans && people && options.fit_bodies) files += ", humans.json, scene.ply, scene.obj";
  if (options.write_masks && people) files += ", masks/";
  std::printf("output      %s/%s\n", out_dir.c_str(), files.c_str());
}

// Every setting pf2_slam reads, in one list: the pipeline's, the input folder's and the built-in
// sequence's.
struct AppSettings {
  pf2::SlamOptions slam;
  pf2::TumSequence::Options input;
  pf2::SyntheticSequence::Options synth;
  std::string distortion = "auto";
};

pf2::Settings declareAppSettings(AppSettings* a) {
  pf2::Settings settings = pf2::slamSettings(&a->slam);
  pf2::declareTumSequenceSettings(&a->input, &settings);
  settings.choice("input.distortion", &a->distortion, {"auto", "none", "fr1", "fr2"},
                  "lens distortion: auto = the published TUM fr1/fr2 values when the folder uses those "
                  "cameras' intrinsics");
  pf2::declareSynthSettings(&a->synth, &settings);
  return settings;
}

// The dedicated options, each standing for one setting.
const std::vector<pf2::SettingShortcut> kShortcuts = {
    {"--detector", "detector.name"},           {"--frames", "run.max_frames"},
    {"--no-map", "map.build", "false"},        {"--pcd", "map.pcd", "true"},
    {"--obj", "map.obj", "true"},              {"--quiet", "run.progress", "false"},
    {"--masks", "run.write_masks", "true"},    {"--calibration", "input.calibration"},
    {"--associations", "input.associations"},  {"--depth-scale", "input.depth_scale"},
    {"--distortion", "input.distortion"},      {"--synth-frames", "synth.frames"},
    {"--synth-people", "synth.people"},        {"--synth-camera", "synth.camera"},
    {"--seed", "synth.seed"},                  {"--no-bodies", "bodies.fit", "false"},
    {"--bodies-every", "bodies.scene_every"}};

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  AppSettings app;
  pf2::Settings settings = declareAppSettings(&app);
  if (pf2::answeredHelpOrSettings(&cli, kUsage, settings)) return 0;
  pf2::readCommandLineSettings(&cli, &settings, kShortcuts);
  pf2::SlamOptions& options = app.slam;
  const std::string out_dir = cli.value("-o", "pf2_output");
  std::optional<std::string> eval_path = cli.value("--eval");
  const std::optional<std::string> gt_format_name = cli.value("--gt-format");
  std::optional<pf2::TrajectoryFormat> gt_format;
  if (gt_format_name) gt_format = pf2::parseTrajectoryFormat(*gt_format_name, "--gt-format");
  const auto positionals = cli.positionals();
  if (positionals.size() > 1) throw pf2::Error("expected at most one SEQUENCE_DIR (see -h)");

  std::string sequence_dir;
  if (positionals.empty()) {
    // The built-in sequence is written out first, so the run reads it like any TUM folder and
    // the user can look at (and re-run on) exactly what was processed.
    if (!exists(out_dir) && ::mkdir(out_dir.c_str(), 0755) != 0) {
      throw pf2::fileError(out_dir, "cannot create output directory");
    }
    sequence_dir = out_dir + "/synthetic";
    const pf2::SyntheticSequence synthetic(app.synth);
    std::fprintf(stderr, "pf2_slam: generating %s into %s\n", synthetic.description().c_str(),
                 sequence_dir.c_str());
    synthetic.writeTumFolder(sequence_dir);
    if (!eval_path) eval_path = sequence_dir + "/groundtruth.txt";
  } else {
    sequence_dir = positionals[0];
  }
  const pf2::TumSequence sequence(sequence_dir, app.input);
  options.tracker.odometry.distortion = lensDistortion(app.distortion, sequence.intrinsics());
  pf2::SlamSystem system(options);
  const pf2::SlamRunSummary s = system.run(sequence, sequence_dir, out_dir);

  printSummary(sequence.description(), s, system.stats());
  if (eval_path) {
    // Default: a Bonn folder as published (rgbd_bonn_*) holds marker poses, anything else camera poses.
    const pf2::TrajectoryFormat format = gt_format.value_or(
        pf2::isBonnDynamicFolder(sequence_dir) ? pf2::TrajectoryFormat::kBonn : pf2::TrajectoryFormat::kTum);
    printAccuracy(pf2::readTrajectory(*eval_path, format), system.trajectory());
  }
  printOutputs(out_dir, options, s.detector);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_slam", run, argc, argv); }
