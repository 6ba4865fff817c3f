#include "sample_run.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace pf2 {
namespace test {

namespace {

constexpr double kFps = 30.0;
constexpr double kPi = 3.14159265358979323846;

// The status of frame i: a stretch of bridged frames, a loss ending in a relocalisation, and a
// second short bridge, at fixed fractions of the run.
TrackStatus statusOf(int i, int frames) {
  if (i >= frames * 30 / 100 && i < frames * 34 / 100) return TrackStatus::kBridged;
  if (i >= frames / 2 && i < frames * 57 / 100) return TrackStatus::kLost;
  if (i == frames * 57 / 100) return TrackStatus::kRelocalised;
  if (i >= frames * 80 / 100 && i < frames * 82 / 100) return TrackStatus::kBridged;
  return TrackStatus::kOk;
}

// The ground truth camera: an ellipse at eye height in a z-up world, looking at its centre.
Eigen::Isometry3d truePose(int i, int frames) {
  const double a = 1.8 * kPi * i / frames;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(2.0 * std::cos(a), 1.4 * std::sin(a), 1.5 + 0.05 * std::sin(3 * a));
  // Camera z (forward) horizontal towards the centre, camera y (down) along world -z.
  const Eigen::Vector3d forward = -T.translation().cwiseProduct(Eigen::Vector3d(1, 1, 0)).normalized();
  const Eigen::Vector3d down(0, 0, -1);
  T.linear().col(2) = forward;
  T.linear().col(1) = down;
  T.linear().col(0) = down.cross(forward);
  return T;
}

// The estimate's world: the first camera's frame (what a SLAM system starts from).
Eigen::Isometry3d estimateWorld(int frames) { return truePose(0, frames).inverse(); }

void addPoses(const SampleOptions& o, std::mt19937* rng, SampleRun* run) {
  std::normal_distribution<double> noise(0.0, 0.004);
  const Eigen::Isometry3d world = estimateWorld(o.frames);
  for (int i = 0; i < o.frames; ++i) {
    const double t = o.start_time + i / kFps;
    const Eigen::Isometry3d gt = truePose(i, o.frames);
    run->ground_truth.push_back({t, gt});
    const TrackStatus status = statusOf(i, o.frames);
    run->result.frame_status.emplace_back(t, status);
    if (!hasPose(status)) continue;
    Eigen::Isometry3d estimate = world * gt;
    const double drift = 0.12 * i / o.frames + (status == TrackStatus::kBridged ? 0.03 : 0.0);
    estimate.translation() += Eigen::Vector3d(drift, -0.5 * drift, 0.2 * drift) +
                              Eigen::Vector3d(noise(*rng), noise(*rng), noise(*rng));
    run->result.trajectory.push_back({t, estimate});
  }
}

// Two people crossing the room, seen while the camera has a pose; positions in the estimate's
// world like the pipeline's.
void addPeople(const SampleOptions& o, std::mt19937* rng, SampleRun* run) {
  std::normal_distribution<double> noise(0.0, 0.01);
  const Eigen::Isometry3d world = estimateWorld(o.frames);
  HumanTrack walker{1, {}}, stroller{2, {}};
  for (int i = 0; i < o.frames; ++i) {
    if (!hasPose(statusOf(i, o.frames))) continue;
    const double t = o.start_time + i / kFps, s = static_cast<double>(i) / o.frames;
    const Eigen::Vector3d jitter(noise(*rng), noise(*rng), 0.0);
    if (s >= 0.05 && s < 0.85) {
      const double u = (s - 0.05) / 0.8;
      walker.points.push_back({t, world * (Eigen::Vector3d(-1.4 + 2.8 * u, -0.6 + 1.1 * u, 0.95) + jitter)});
    }
    if (s >= 0.35) {
      const double b = kPi * (s - 0.35) / 0.65;
      const Eigen::Vector3d p(0.8 * std::cos(b), -0.9 + 0.8 * std::sin(b), 0.9);
      stroller.points.push_back({t, world * (p + jitter)});
    }
  }
  run->result.has_humans = true;
  run->result.humans = {walker, stroller};
}

// Per-frame stages as the pipeline times them; the first detector call is slow (model warm-up).
void addStages(const SampleOptions& o, std::mt19937* rng, SampleRun* run) {
  std::normal_distribution<double> unit(0.0, 1.0);
  for (int i = 0; i < o.frames; ++i) {
    const TrackStatus status = statusOf(i, o.frames);
    const double detect = i == 0 ? 420.0 : 27.0 + 3.0 * std::abs(unit(*rng));
    const double filter = 4.0 + 0.8 * std::abs(unit(*rng));
    const double track = (status == TrackStatus::kOk ? 11.0 : 19.0) + 2.0 * std::abs(unit(*rng));
    const double humans = 0.05 + 0.01 * std::abs(unit(*rng));
    run->stages.add("load", 3.0 + 0.5 * std::abs(unit(*rng)));
    run->stages.add("detect", detect);
    run->stages.add("filter", filter);
    run->stages.add("track", track);
    run->stages.add("humans", humans);
    run->stages.add("frame", detect + filter + track + humans + 1.5);
    if (i % 12 == 0) run->stages.add("map", 22.0 + 4.0 * std::abs(unit(*rng)));
  }
}

void fillSummary(SampleRun* run) {
  SlamRunSummary& s = run->result.summary;
  s.frames = static_cast<int>(run->result.frame_status.size());
  for (const auto& frame : run->result.frame_status) {
    s.tracked += hasPose(frame.second) ? 1 : 0;
    s.lost += frame.second == TrackStatus::kLost ? 1 : 0;
    s.bridged += frame.second == TrackStatus::kBridged ? 1 : 0;
    s.relocalised += frame.second == TrackStatus::kRelocalised ? 1 : 0;
  }
  s.keyframes = s.frames / 12;
  s.loop_closures = 1;
  s.local_edges = 2 * s.keyframes;
  s.seconds = s.frames / 18.5;
  s.fps = s.seconds > 0 ? s.frames / s.seconds : 0.0;
  s.body_fits_offered = 40;
  s.body_fits_skipped = 3;
  s.detector = "learned";
}

}  // namespace

RunReportInput SampleRun::input(bool with_ground_truth) const {
  RunReportInput input;
  input.title = "synthetic loop, 2 people";
  input.settings = settings;
  input.result = &result;
  input.stages = &stages;
  if (with_ground_truth) input.ground_truth = &ground_truth;
  return input;
}

void makeSampleRun(const SampleOptions& options, SampleRun* run) {
  std::mt19937 rng(static_cast<std::mt19937::result_type>(options.seed));
  addPoses(options, &rng, run);
  addPeople(options, &rng, run);
  addStages(options, &rng, run);
  fillSummary(run);
  run->settings = {{"detector.name", "learned"},       {"filter.dilation", "5"},
                   {"tracker.max_bridged", "15"},      {"map.build", "true"},
                   {"map.voxel_size", "0.01"},         {"humans.reid_window", "10"},
                   {"bodies.fit", "true"},             {"input.calibration", "camera <fr3> & \"quoted\""},
                   {"run.max_frames", "0"}};
}

}  // namespace test
}  // namespace pf2
