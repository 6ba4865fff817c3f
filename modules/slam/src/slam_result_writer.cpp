// writeSlamResult: a run's result folder (declared in slam_system.h).
#include <filesystem>
#include <sstream>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"
#include "pf2/humans/body_tracks_io.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/slam/scene_export.h"
#include "pf2/slam/slam_system.h"

namespace pf2 {
namespace {

// Each frame's timestamp and tracking status ("tracked", "bridged", "relocalised", "lost").
std::string frameStatusJson(const std::vector<std::pair<double, TrackStatus>>& frames) {
  std::ostringstream out;
  out.precision(17);
  out << "[";
  for (size_t i = 0; i < frames.size(); ++i) {
    out << (i ? "," : "") << "{\"timestamp\":" << frames[i].first << ",\"status\":\"" << toString(frames[i].second)
        << "\"}";
  }
  out << "]";
  return out.str();
}

std::string summaryJson(const SlamResult& result, const StageStats& stages) {
  const SlamRunSummary& s = result.summary;
  std::ostringstream out;
  out.precision(6);
  out << "{\"frames\":" << s.frames << ",\"tracked\":" << s.tracked << ",\"lost\":" << s.lost
      << ",\"relocalised\":" << s.relocalised << ",\"bridged\":" << s.bridged
      << ",\"interpolated\":" << s.interpolated
      << ",\"keyframes\":" << s.keyframes << ",\"loop_closures\":" << s.loop_closures
      << ",\"local_edges\":" << s.local_edges << ",\"map_refusions\":" << s.map_refusions
      << ",\"trajectory_acceleration_noise\":" << s.acceleration_noise << ",\"dropped\":" << s.dropped
      << ",\"stopped\":" << (s.stopped ? "true" : "false")
      << ",\"body_fits_offered\":" << s.body_fits_offered << ",\"body_fits_skipped\":" << s.body_fits_skipped
      << ",\"seconds\":" << s.seconds << ",\"fps\":" << s.fps << ",\"detector\":\"" << s.detector
      << "\",\"world_up\":[" << s.up_w.x() << "," << s.up_w.y() << "," << s.up_w.z()
      << "],\"world_up_estimated\":" << (s.up_estimated ? "true" : "false") << ",\"stages\":" << stages.toJson()
      << ",\"tracker_stages\":" << result.tracker_stages_json << ",\"body_stages\":" << result.body_stages_json
      << ",\"frame_status\":" << frameStatusJson(result.frame_status) << "}\n";
  return out.str();
}

// Every file a run can write into its folder (masks/ is handled by runToFolder).
const char* const kOutputFiles[] = {"trajectory.txt", "stats.json", "report.html", "map.ply", "map.bt", "map.ot",
                                    "map.pcd", "map.obj", "humans.txt", "humans.json", "scene.ply", "scene.obj"};

// The files of one result, into `dir`.
void writeFiles(const std::string& dir, const SlamResult& result, StageStats* stages, const ExtraFiles& extra_files) {
  writeTrajectory(dir + "/trajectory.txt", result.trajectory);
  if (result.has_humans) writeHumanTracks(dir + "/humans.txt", result.humans);
  TriangleMesh static_map;
  if (result.map) {
    ScopedStageTimer timer(stages, "map_export");
    static_map = result.map->extractMesh();
    result.map->exportMap(dir, result.map_files, static_map);
  }
  if (result.body_model) {
    ScopedStageTimer timer(stages, "scene_export");
    writeBodyTracksJson(dir + "/humans.json", result.bodies);
    const TriangleMesh scene = buildScene(static_map, result.bodies, *result.body_model, result.scene);
    saveMeshPly(scene, dir + "/scene.ply");
    saveMeshObj(scene, dir + "/scene.obj");
  }
  const std::string json = summaryJson(result, *stages);
  writeFileAtomically(dir + "/stats.json", [&](std::ostream& out) { out << json; });
  if (extra_files) extra_files(dir, result);
}

}  // namespace

// The files are written into a staging folder inside out_dir and moved into place only when all
// of them were written: a failure (a full disk during the map export) leaves out_dir as it was.
// Moving them is renames within one file system: no partial file is ever visible.
void writeSlamResult(const std::string& out_dir, const SlamResult& result, StageStats* stages,
                     const ExtraFiles& extra_files) {
  namespace fs = std::filesystem;
  const fs::path staging = fs::path(out_dir) / ".pf2_result.partial";
  std::error_code ignored;
  fs::remove_all(staging, ignored);
  if (!fs::create_directories(staging, ignored) && !fs::is_directory(staging)) {
    throw fileError(staging.string(), "cannot create the staging folder for the outputs");
  }
  try {
    writeFiles(staging.string(), result, stages, extra_files);
    // stats.json marks a complete run: the old one goes first and the new one comes last, so a
    // folder interrupted while the files move (a kill, a power cut) has no stats.json rather
    // than one that belongs to other files.
    fs::remove(fs::path(out_dir) / "stats.json");
    // The files of an earlier run this one does not write (a map when this run has none) would
    // sit beside the new ones as if they belonged to them.
    for (const char* name : kOutputFiles) {
      if (!fs::exists(staging / name)) fs::remove(fs::path(out_dir) / name);
    }
    for (const fs::directory_entry& entry : fs::directory_iterator(staging)) {
      if (entry.path().filename() != "stats.json") fs::rename(entry.path(), fs::path(out_dir) / entry.path().filename());
    }
    fs::rename(staging / "stats.json", fs::path(out_dir) / "stats.json");
  } catch (const fs::filesystem_error& e) {
    fs::remove_all(staging, ignored);
    throw fileError(out_dir, std::string("cannot write the outputs: ") + e.what());
  } catch (...) {
    fs::remove_all(staging, ignored);
    throw;
  }
  fs::remove_all(staging, ignored);
}

}  // namespace pf2
