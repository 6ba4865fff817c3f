// writeSlamResult: a run's result folder (declared in slam_system.h).
#include <sstream>

#include "pf2/core/atomic_file.h"
#include "pf2/io/trajectory_io.h"
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
      << ",\"keyframes\":" << s.keyframes << ",\"loop_closures\":" << s.loop_closures
      << ",\"local_edges\":" << s.local_edges
      << ",\"seconds\":" << s.seconds << ",\"fps\":" << s.fps << ",\"detector\":\"" << s.detector
      << "\",\"stages\":" << stages.toJson() << ",\"tracker_stages\":" << result.tracker_stages_json
      << ",\"frame_status\":" << frameStatusJson(result.frame_status) << "}\n";
  return out.str();
}

}  // namespace

void writeSlamResult(const std::string& out_dir, const SlamResult& result, StageStats* stages) {
  writeTrajectory(out_dir + "/trajectory.txt", result.trajectory);
  if (result.has_humans) writeHumanTracks(out_dir + "/humans.txt", result.humans);
  if (result.map) {
    ScopedStageTimer timer(stages, "map_export");
    result.map->exportMap(out_dir, result.map_files);
  }
  const std::string json = summaryJson(result, *stages);
  writeFileAtomically(out_dir + "/stats.json", [&](std::ostream& out) { out << json; });
}

}  // namespace pf2
