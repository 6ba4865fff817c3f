// pf2_humans_eval: scores a pf2_slam run's humans.txt against a pf2_synth sequence's ground truth
// (gt/people.txt, pelvis per person per frame). The run's world frame (the first tracked camera)
// is moved into the ground truth's by the first tracked frame's ground-truth pose, as
// pf2_slam_map_eval does for the map. Person-frames counted: those in gt/boxes.txt (the person is
// in view) with a visible fraction of at least --min-visible, within the run's time span.
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <utility>

#include "pf2/core/command_line.h"
#include "pf2/core/error.h"
#include "pf2/detection/gt_detector.h"
#include "pf2/eval/body_metrics.h"
#include "pf2/eval/human_metrics.h"
#include "pf2/humans/body_tracks_io.h"
#include "pf2/humans/human_track.h"
#include "pf2/humans/human_tracker.h"
#include "pf2/io/trajectory_io.h"

namespace {

const char* kUsage =
    "Usage: pf2_humans_eval SEQUENCE_DIR RUN_DIR [--match-distance M] [--min-visible F] [--json]\n"
    "                       [--reassociate paper|predicted [--gate G] [--max-missed N]]\n"
    "Scores RUN_DIR/humans.txt (world frame of RUN_DIR/trajectory.txt) against\n"
    "SEQUENCE_DIR/gt/people.txt: per-frame matching within M metres (default 0.5) as CLEAR MOT\n"
    "does (a person keeps last frame's track while it stays within M, the rest by minimum distance),\n"
    "position error, identity switches, fragmentations and recall of the person-frames in view\n"
    "(gt/boxes.txt, visible fraction >= F, default 0). --reassociate drops the run's ids and\n"
    "associates its centres again with HumanTracker (same centres, other association options).\n"
    "When RUN_DIR has humans.json, its bodies are scored too against SEQUENCE_DIR/gt/joints.txt:\n"
    "MPJPE (mean per-joint position error, the 24 joints, world frame) of each body frame matched to\n"
    "the true person whose pelvis is nearest within M, over all body frames and over fitted ones,\n"
    "and the median error of each joint.\n";

// The run's centres given new ids by a HumanTracker, frame by frame (every frame of the run,
// so frames without a centre age the tracks as they do in pf2_slam).
std::vector<pf2::HumanTrack> reassociate(const std::vector<pf2::HumanTrack>& tracks, const pf2::Trajectory& run,
                                         const pf2::HumanTracker::Options& options) {
  std::map<double, std::vector<Eigen::Vector3d>> centres_at;
  for (const pf2::StampedPose& pose : run) centres_at[pose.timestamp];
  for (const pf2::HumanTrack& track : tracks) {
    for (const pf2::HumanTrackPoint& point : track.points) centres_at[point.timestamp].push_back(point.p_w);
  }
  pf2::HumanTracker tracker(options);
  for (const auto& [stamp, centres] : centres_at) tracker.update(stamp, centres);
  return tracker.tracks();
}

// (timestamp, id) of each person in view, from gt/boxes.txt.
std::set<std::pair<double, int>> peopleInView(const std::string& path, double min_visible) {
  std::set<std::pair<double, int>> in_view;
  for (const pf2::GroundTruthBox& b : pf2::readGroundTruthBoxes(path)) {
    if (b.visible_fraction >= min_visible) in_view.insert({b.timestamp, b.id});
  }
  return in_view;
}

void printBodyMetrics(const pf2::BodyMetrics& b) {
  std::printf("bodies: %d body frames matched (%d unmatched), %d fitted\n", b.body_frames, b.unmatched,
              b.mpjpe_fitted.count);
  std::printf("MPJPE all frames: mean %.1f median %.1f mm; fitted frames: mean %.1f median %.1f mm\n",
              1000 * b.mpjpe.mean, 1000 * b.mpjpe.median, 1000 * b.mpjpe_fitted.mean, 1000 * b.mpjpe_fitted.median);
  std::printf("per joint, median mm:");
  for (int j = 0; j < pf2::kBodyJointCount; ++j) std::printf(" %s %.0f", pf2::kBodyJointNames[j], 1000 * b.joint_median[j]);
  std::printf("\n");
}

void printStats(const char* name, const pf2::ErrorStatistics& s) {
  std::printf("%-22s rmse %.3f  median %.3f  mean %.3f  max %.3f m  (%d)\n", name, s.rmse, s.median,
              s.mean, s.max, s.count);
}

int run(int argc, char** argv) {
  pf2::CommandLine cli(argc, argv);
  if (cli.helpRequested()) {
    std::cout << kUsage;
    return 0;
  }
  pf2::HumanMetricsOptions options;
  options.match_distance = cli.number("--match-distance", options.match_distance);
  const double min_visible = cli.number("--min-visible", 0.0);
  const bool json = cli.flag("--json");
  const std::optional<std::string> association = cli.value("--reassociate");
  pf2::HumanTracker::Options tracker_options;
  tracker_options.gate = cli.number("--gate", tracker_options.gate);
  tracker_options.max_missed = cli.integer("--max-missed", tracker_options.max_missed);
  if (association) tracker_options.association = pf2::humanAssociationFromName(*association);
  const auto positionals = cli.positionals();
  if (positionals.size() != 2) throw pf2::Error("expected SEQUENCE_DIR and RUN_DIR (see -h)");
  const std::string sequence = positionals[0], run_dir = positionals[1];

  const pf2::Trajectory ground_truth = pf2::readTrajectory(sequence + "/groundtruth.txt");
  const pf2::Trajectory estimate = pf2::readTrajectory(run_dir + "/trajectory.txt");
  if (estimate.empty()) throw pf2::fileError(run_dir + "/trajectory.txt", "no poses");
  Eigen::Isometry3d T_gt_first;
  if (!pf2::interpolateAt(ground_truth, estimate.front().timestamp, 0.1, &T_gt_first)) {
    throw pf2::fileError(sequence + "/groundtruth.txt", "no pose at the run's first tracked frame");
  }
  const Eigen::Isometry3d T_gt_est = T_gt_first * estimate.front().T_w_c.inverse();

  std::vector<pf2::HumanTrack> tracks = pf2::readHumanTracks(run_dir + "/humans.txt");
  if (association) tracks = reassociate(tracks, estimate, tracker_options);
  for (pf2::HumanTrack& track : tracks) {
    for (pf2::HumanTrackPoint& point : track.points) point.p_w = T_gt_est * point.p_w;
  }
  const auto in_view = peopleInView(sequence + "/gt/boxes.txt", min_visible);
  const double first = estimate.front().timestamp - options.max_time_difference;
  const double last = estimate.back().timestamp + options.max_time_difference;
  std::vector<pf2::HumanTrack> people = pf2::readHumanTracks(sequence + "/gt/people.txt");
  for (pf2::HumanTrack& person : people) {
    std::vector<pf2::HumanTrackPoint> kept;
    for (const pf2::HumanTrackPoint& point : person.points) {
      if (point.timestamp >= first && point.timestamp <= last && in_view.count({point.timestamp, person.id})) {
        kept.push_back(point);
      }
    }
    person.points = std::move(kept);
  }

  const pf2::HumanMetrics m = pf2::evaluateHumanTracks(people, tracks, options);
  std::printf("person-frames %d, matched %d (recall %.3f), tracks %d, estimates %d (%d unmatched)\n",
              m.frames, m.matched, m.recall, m.tracks, m.estimates, m.unmatched_estimates);
  std::printf("id switches %d, fragmentations %d\n", m.id_switches, m.fragmentations);
  printStats("error", m.error);
  printStats("error without offset", m.error_without_offset);
  for (const pf2::HumanPersonMetrics& p : m.people) {
    std::printf("person %d: track %d, %d/%d frames, %d switches, %d fragmentations, rmse %.3f m, "
                "offset (%.3f %.3f %.3f) m, rmse without offset %.3f m\n",
                p.gt_id, p.track, p.matched, p.frames, p.id_switches, p.fragmentations, p.error.rmse,
                p.mean_offset.x(), p.mean_offset.y(), p.mean_offset.z(), p.error_without_offset.rmse);
  }
  std::string body_json;
  if (!association && std::ifstream(run_dir + "/humans.json")) {
    const pf2::BodyMetrics b = pf2::evaluateBodies(pf2::readBodyTracksJson(run_dir + "/humans.json"), T_gt_est,
                                                   pf2::readGroundTruthJoints(sequence + "/gt/joints.txt"),
                                                   options.match_distance);
    printBodyMetrics(b);
    char text[256];
    std::snprintf(text, sizeof(text),
                  ",\"body_frames\":%d,\"mpjpe_mean_mm\":%.1f,\"mpjpe_median_mm\":%.1f,"
                  "\"mpjpe_fitted_mean_mm\":%.1f,\"mpjpe_fitted_median_mm\":%.1f,\"fitted_frames\":%d",
                  b.body_frames, 1000 * b.mpjpe.mean, 1000 * b.mpjpe.median, 1000 * b.mpjpe_fitted.mean,
                  1000 * b.mpjpe_fitted.median, b.mpjpe_fitted.count);
    body_json = text;
  }
  if (json) {
    std::printf("{\"frames\":%d,\"matched\":%d,\"recall\":%.4f,\"tracks\":%d,\"estimates\":%d,"
                "\"unmatched_estimates\":%d,\"id_switches\":%d,\"fragmentations\":%d,\"rmse\":%.4f,"
                "\"median\":%.4f,\"rmse_without_offset\":%.4f,\"median_without_offset\":%.4f%s}\n",
                m.frames, m.matched, m.recall, m.tracks, m.estimates, m.unmatched_estimates,
                m.id_switches, m.fragmentations, m.error.rmse, m.error.median,
                m.error_without_offset.rmse, m.error_without_offset.median, body_json.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) { return pf2::runApp("pf2_humans_eval", run, argc, argv); }
