// pf2_slam: dynamic RGB-D SLAM on a TUM-layout folder, or on the built-in synthetic sequence.
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdlib>
#include <filesystem>

#include <cstdio>
#include <iostream>
#include <string>

#include <opencv2/core/utility.hpp>

#include "pf2/core/app_settings.h"
#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/core/settings.h"
#include "pf2/eval/trajectory_metrics.h"
#include "pf2/io/frame_streams.h"
#include "pf2/io/openni2_stream.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/io/tum_sequence.h"
#include "pf2/io/tum_sequence_settings.h"
#include "pf2/registration/rgbd_odometry.h"
#include "pf2/report/run_report.h"
#include "pf2/slam/slam_runner.h"
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
    "  --preset NAME        a named set of settings (listed at the end), before --config and --set\n"
    "Each option below is a setting applied after --set: --frames N is --set run.max_frames=N.\n"
    "  --frames N           process only the first N frames\n"
    "  --no-map             track only; no TSDF/OctoMap\n"
    "  --pcd                also write map.pcd (the mesh vertices as coloured points)\n"
    "  --obj                also write map.obj (the mesh as Wavefront OBJ with vertex colours)\n"
    "  --masks              also write masks/<timestamp>.png per frame (255 = depth removed from the\n"
    "                       map, filter.backfill_frames, give_back_views and seen_through_views\n"
    "                       included)\n"
    "  --no-bodies          no body fits: humans.txt from the eq. 2 centres, no humans.json/scene.*\n"
    "  --bodies-every N     scene.ply/.obj also show every N-th body along each track\n"
    "  --calibration FILE   camera calibration file (default: camera.txt in the folder or TUM preset)\n"
    "  --associations FILE  rgb/depth associations instead of matching rgb.txt and depth.txt\n"
    "  --depth-scale S      depth PNG units per metre (default 5000)\n"
    "  --distortion D       auto (TUM fr1/fr2 lens distortion for those presets), none, fr1, fr2\n"
    "  --quiet              no progress line\n"
    "Input (besides SEQUENCE_DIR, a TUM or Bonn folder):\n"
    "  --device openni2[:URI]  a live OpenNI2 camera (Kinect, Xtion, Astra): the first one, the\n"
    "                       one with this URI or '#N', or an OpenNI2 recording (URI = FILE.oni);\n"
    "                       real time: frames that arrive while the pipeline is busy are dropped\n"
    "                       (and counted); Ctrl-C ends the run and writes its outputs\n"
    "  --record DIR         with --device: also save every frame as a TUM folder (DIR new or empty)\n"
    "  --realtime           a recording at its own pace, dropping frames like a live camera\n"
    "                       (default: every frame, as fast as the machine goes)\n"
    "Built-in sequence:\n"
    "  --synth-frames N     frames (default 300)   --synth-people K  people 0..5 (default 3)\n"
    "  --synth-camera M     static|xyz|halfsphere|rpy|loop|above (default xyz)   --seed S (default 1)\n"
    "  -h, --help           this text\n";

// kUsage and the presets, each with its meaning and settings (declared once, in slamPresets()).
std::string usage() {
  std::string text = std::string(kUsage) + "Presets (--preset NAME):\n";
  for (const pf2::SlamPreset& preset : pf2::slamPresets()) {
    text += "  " + preset.name + ": " + preset.meaning + "\n   ";
    for (const std::string& assignment : preset.assignments) text += " --set " + assignment;
    text += "\n";
  }
  return text;
}

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

// The run's figures: frames and their status, keyframes, speed per stage.
void printSummary(const std::string& sequence, const pf2::SlamRunSummary& s, const pf2::StageStats& stats) {
  std::printf("sequence    %s\n", sequence.c_str());
  std::printf("detector    %s\n", s.detector.c_str());
  std::printf("frames      %d (posed %d: bridged %d of them %d interpolated, relocalised %d; lost %d)\n", s.frames,
              s.tracked, s.bridged, s.interpolated, s.relocalised, s.lost);
  std::printf("keyframes   %d (local edges %d, loop closures %d)\n", s.keyframes, s.local_edges, s.loop_closures);
  std::printf("fps         %.1f end to end (%.1f s)\n", s.fps, s.seconds);
  if (s.acceleration_noise > 0)
    std::printf("smoothing   trajectory.txt with an acceleration noise of %.2f m/s^2\n", s.acceleration_noise);
  if (s.dropped > 0) std::printf("dropped     %d frames arrived while the pipeline was busy (real time)\n", s.dropped);
  if (s.stopped) std::printf("stopped     early (Ctrl-C): the outputs cover the %d frames processed\n", s.frames);
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
  std::string files = "trajectory.txt, stats.json, report.html";
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

// Ctrl-C asks the run to stop after the frames in flight and to write its outputs; later ones are
// only answered, so that no Ctrl-C ever leaves a folder mixing two runs (Ctrl-\ still aborts).
std::atomic<bool> g_stop_requested{false};

void onInterrupt(int) {
  const bool again = g_stop_requested.exchange(true);
  const char first[] = "\npf2_slam: stopping after the frames in flight, then writing the outputs\n";
  const char later[] = "\npf2_slam: still finishing and writing the outputs (Ctrl-\\ aborts and may leave them incomplete)\n";
  [[maybe_unused]] const ssize_t written =
      again ? ::write(STDERR_FILENO, later, sizeof(later) - 1) : ::write(STDERR_FILENO, first, sizeof(first) - 1);
}

// Where the frames come from and where the results go, from the command line.
struct Inputs {
  std::string out_dir;
  std::string sequence_dir;             // a recording (TUM layout), or empty with a device
  std::optional<std::string> device;    // --device openni2[:URI]: the URI ("" = first camera)
  std::string record_dir;               // --record DIR (live only)
  bool realtime = false;                // --realtime: a recording at its own pace, dropping frames
  std::optional<std::string> eval_path;
  std::optional<pf2::TrajectoryFormat> gt_format;
};

Inputs readInputs(pf2::CommandLine* cli) {
  Inputs in;
  in.out_dir = cli->value("-o", "pf2_output");
  in.eval_path = cli->value("--eval");
  if (const auto name = cli->value("--gt-format")) in.gt_format = pf2::parseTrajectoryFormat(*name, "--gt-format");
  if (const auto device = cli->value("--device")) {
    if (device->rfind("openni2", 0) != 0 || (device->size() > 7 && (*device)[7] != ':')) {
      throw pf2::Error("option --device: expected openni2 or openni2:URI, got '" + *device + "'");
    }
    in.device = device->size() > 8 ? device->substr(8) : "";
  }
  in.record_dir = cli->value("--record", "");
  in.realtime = cli->flag("--realtime");
  const auto positionals = cli->positionals();
  if (positionals.size() > 1) throw pf2::Error("expected at most one SEQUENCE_DIR (see -h)");
  if (!positionals.empty() && in.device) throw pf2::Error("give a SEQUENCE_DIR or --device, not both");
  if (!positionals.empty()) in.sequence_dir = positionals[0];
  if (!in.record_dir.empty() && !in.device) throw pf2::Error("option --record: records a live --device only");
  return in;
}

// The built-in sequence is written out first, so the run reads it like any TUM folder and the
// user can look at (and re-run on) exactly what was processed.
void generateSyntheticSequence(const AppSettings& app, Inputs* in) {
  pf2::makeOutputFolder(in->out_dir);
  in->sequence_dir = in->out_dir + "/synthetic";
  const pf2::SyntheticSequence synthetic(app.synth);
  std::fprintf(stderr, "pf2_slam: generating %s into %s\n", synthetic.description().c_str(), in->sequence_dir.c_str());
  synthetic.writeTumFolder(in->sequence_dir);
  if (!in->eval_path) in->eval_path = in->sequence_dir + "/groundtruth.txt";
}

// The ground truth, read before the run: a missing or broken file must not cost a run.
std::optional<pf2::Trajectory> readGroundTruth(const Inputs& in) {
  if (!in.eval_path) return std::nullopt;
  // Default: a Bonn folder as published (rgbd_bonn_*) holds marker poses, anything else camera poses.
  const pf2::TrajectoryFormat format = in.gt_format.value_or(
      pf2::isBonnDynamicFolder(in.sequence_dir) ? pf2::TrajectoryFormat::kBonn : pf2::TrajectoryFormat::kTum);
  pf2::Trajectory truth = pf2::readTrajectory(*in.eval_path, format);
  if (truth.empty()) throw pf2::fileError(*in.eval_path, "no poses in the ground truth");
  return truth;
}

// A live camera, or a recording: every frame decoded ahead (offline), or at its own pace
// dropping what the pipeline cannot take (--realtime).
std::unique_ptr<pf2::FrameStream> openStream(const Inputs& in, const pf2::FrameSource* recording,
                                             const pf2::SlamOptions& options, pf2::StageStats* stats) {
  if (in.device) return std::make_unique<pf2::OpenNI2Stream>(*in.device, in.record_dir);
  if (in.realtime) return std::make_unique<pf2::ClockedStream>(*recording);
  return std::make_unique<pf2::RecordedStream>(*recording, static_cast<size_t>(options.max_frames),
                                               options.prefetch_frames, stats);
}

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  AppSettings app;
  pf2::Settings settings = declareAppSettings(&app);
  if (pf2::answeredHelpOrSettings(&cli, usage(), settings)) return 0;
  if (const auto preset = cli.value("--preset")) pf2::applySlamPreset(*preset, &settings);
  pf2::readCommandLineSettings(&cli, &settings, kShortcuts);
  pf2::SlamOptions& options = app.slam;
  Inputs in = readInputs(&cli);
  if (in.sequence_dir.empty() && !in.device) generateSyntheticSequence(app, &in);
  const std::optional<pf2::Trajectory> truth = readGroundTruth(in);
  std::unique_ptr<pf2::TumSequence> recording;
  if (!in.device) {
    recording = std::make_unique<pf2::TumSequence>(in.sequence_dir, app.input);
    if (recording->size() == 0) throw pf2::fileError(in.sequence_dir, "the sequence has no frames");
    options.tracker.odometry.distortion = lensDistortion(app.distortion, recording->intrinsics());
  }
  if (options.opencv_threads > 0) cv::setNumThreads(options.opencv_threads);
  std::string detector_name;
  pf2::SlamSystem system(options, pf2::createSlamDetector(options, in.sequence_dir, &detector_name));
  const std::unique_ptr<pf2::FrameStream> stream = openStream(in, recording.get(), options, &system.stats());
  std::signal(SIGINT, onInterrupt);
  pf2::SlamRunner::Options runner;
  runner.progress = options.progress;
  // report.html is written with the other outputs, as part of the same set.
  const auto report = [&](const std::string& dir, const pf2::SlamResult& result) {
    pf2::RunReportInput page;
    page.title = std::filesystem::path(in.device ? stream->description() : in.sequence_dir).filename().string();
    if (page.title.empty()) page.title = stream->description();
    for (const std::string& key : settings.keys()) page.settings.emplace_back(key, settings.value(key));
    page.result = &result;
    page.stages = &system.stats();
    page.ground_truth = truth ? &*truth : nullptr;
    pf2::writeRunReport(dir + "/report.html", page);
  };
  const pf2::SlamResult result =
      pf2::runToFolder(&system, stream.get(), in.out_dir, runner, &g_stop_requested, report);
  std::signal(SIGINT, SIG_DFL);

  printSummary(stream->description(), result.summary, system.stats());
  if (result.map && result.map->tsdf().blockCount() == 0) {
    std::fprintf(stderr, "pf2_slam: warning: the map is empty: no depth was fused (every measurement beyond "
                         "map.max_depth = %g m, removed, or no frame posed)\n", options.mapper.tsdf.max_depth);
  }
  if (truth) printAccuracy(*truth, result.trajectory);
  printOutputs(in.out_dir, options, result.summary.detector);
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_slam", run, argc, argv); }
