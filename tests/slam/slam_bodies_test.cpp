// Bodies end to end: pf2_slam's own learned detector on a small generated sequence (60 frames,
// static camera, two people): humans.json read back, its joints recomputed from pose and shape,
// the fitted pelvis against the true one, and scene.ply read back through PCL. Skipped when the
// learned detector's models are not installed (scripts/fetch_models.sh).
#include <map>

#include <gtest/gtest.h>

#include "pf2/detection/learned_models.h"
#include "pf2/humans/body_tracks_io.h"
#include "pf2/humans/human_track.h"
#include "pf2/io/trajectory_io.h"
#include "pf2/io/tum_sequence.h"
#include "pf2/slam/slam_system.h"
#include "pf2/surface/triangle_mesh.h"
#include "pf2/synth/synthetic_sequence.h"

namespace pf2 {
namespace {

TEST(SlamBodies, LearnedDetectorFitsBodiesThatReadBackAndLieAtThePeople) {
  if (!humanModelAvailable("selfie") || !humanModelAvailable("movenet-multipose")) {
    GTEST_SKIP() << "no models; run scripts/fetch_models.sh";
  }
  SyntheticSequence::Options synth;
  synth.frames = 60;
  synth.people = 2;
  synth.camera = CameraMotion::kStatic;
  const std::string folder = testing::TempDir() + "pf2_bodies_sequence";
  SyntheticSequence(synth).writeTumFolder(folder);
  SlamOptions options;
  options.detector = "learned";
  options.progress = false;
  options.tracker.asynchronous_backend = false;
  options.bodies.asynchronous = false;  // every offered fit runs: the same bodies on every run
  options.mapper.build_occupancy = false;
  const std::string run = testing::TempDir() + "pf2_bodies_run";
  const SlamRunSummary summary = SlamSystem(options).run(TumSequence(folder), folder, run);
  EXPECT_GT(summary.body_fits_offered, 10);
  EXPECT_EQ(summary.body_fits_skipped, 0);

  const BodyModel model = BodyModel::loadDefault();
  const std::vector<BodyTrack> tracks = readBodyTracksJson(run + "/humans.json");
  ASSERT_FALSE(tracks.empty());
  // Every frame: the joints follow from pose, shape and translation (within 1 mm).
  int fitted = 0;
  size_t frames = 0;
  for (const BodyTrack& track : tracks) {
    for (const BodyTrackFrame& f : track.frames) {
      const auto posed = model.posedJoints(f.body_w);
      for (int j = 0; j < kBodyJointCount; ++j) {
        ASSERT_LT((posed[j] - f.joints_w[j]).norm(), 1e-3) << track.id << " " << j;
      }
      fitted += f.fitted;
      ++frames;
    }
  }
  EXPECT_GT(fitted, 10);
  // humans.txt is the same pelvis.
  const std::vector<HumanTrack> people = readHumanTracks(run + "/humans.txt");
  ASSERT_EQ(people.size(), tracks.size());
  EXPECT_LT((people[0].points[0].p_w - tracks[0].frames[0].pelvis_w).norm(), 1e-5);

  // The fitted pelvis against the true pelvis (gt/people.txt, room frame; the run's world is the
  // first camera's, moved into the room by the first pose's truth): most within 15 cm.
  const Trajectory truth = readTrajectory(folder + "/groundtruth.txt");
  const Trajectory estimate = readTrajectory(run + "/trajectory.txt");
  const Eigen::Isometry3d T_gt_est = truth.front().T_w_c * estimate.front().T_w_c.inverse();
  std::map<long long, std::vector<Eigen::Vector3d>> true_pelvis;
  for (const HumanTrack& person : readHumanTracks(folder + "/gt/people.txt")) {
    for (const HumanTrackPoint& p : person.points) true_pelvis[std::llround(p.timestamp * 1e6)].push_back(p.p_w);
  }
  int close = 0, scored = 0;
  for (const BodyTrack& track : tracks) {
    for (const BodyTrackFrame& f : track.frames) {
      if (!f.fitted) continue;
      double nearest = 1e9;
      for (const Eigen::Vector3d& p : true_pelvis[std::llround(f.timestamp * 1e6)]) {
        nearest = std::min(nearest, (T_gt_est * f.pelvis_w - p).norm());
      }
      close += nearest < 0.15;
      ++scored;
    }
  }
  std::printf("%zu tracks, %zu body frames, %d fitted, %d of them within 15 cm of a true pelvis\n", tracks.size(),
              frames, fitted, close);
  EXPECT_GE(close, 0.8 * scored);

  // scene.ply: map, one body per track, each track's points; read back through PCL.
  const TriangleMesh map = loadMeshPly(run + "/map.ply");
  const TriangleMesh scene = loadMeshPly(run + "/scene.ply");
  EXPECT_EQ(scene.vertices.size(), map.vertices.size() + tracks.size() * model.vertexCount() + frames);
}

}  // namespace
}  // namespace pf2
