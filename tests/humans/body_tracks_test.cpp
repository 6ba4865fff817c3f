// The bodies' stage: fits in their own thread (BodyTrackFitter), their placement in the world by
// eq. 4 with the final camera poses, interpolation and smoothing (BodyTrackAssembler), and
// humans.json written and read back.
#include <cmath>
#include <cstdio>
#include <functional>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"
#include "pf2/core/median.h"
#include "pf2/humans/body_track_fitter.h"
#include "pf2/humans/body_tracks.h"
#include "pf2/humans/body_tracks_io.h"

namespace pf2 {
namespace {

const BodyModel& model() {
  static const BodyModel loaded = BodyModel::loadDefault();
  return loaded;
}

// A person 2.5 m in front of the camera, walking pose, some shape.
BodyParameters personInCamera() {
  BodyParameters body;
  body.shape[0] = 0.5;
  body.shape[1] = -0.3;
  body.pose[0] = Eigen::Vector3d(M_PI, 0, 0);  // upright in the camera (y down): rotated 180° about x
  body.pose[1] = Eigen::Vector3d(-0.4, 0, 0);
  body.pose[2] = Eigen::Vector3d(0.3, 0, 0);
  body.pose[16] = Eigen::Vector3d(0, 0, -1.2);
  body.pose[17] = Eigen::Vector3d(0, 0, 1.2);
  body.translation = Eigen::Vector3d(0.2, 0.1, 2.5) - model().restJoints(body.shape)[0];
  return body;
}

Eigen::Isometry3d cameraPose(double angle, const Eigen::Vector3d& t) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(angle, Eigen::Vector3d(0.2, 1, 0.1).normalized()).toRotationMatrix();
  T.translation() = t;
  return T;
}

BodyTrackFit fitAt(int frame, double stamp, const BodyParameters& body_c, int keyframe = 0) {
  BodyTrackFit fit;
  fit.track_id = 7;
  fit.frame_index = frame;
  fit.timestamp = stamp;
  fit.keyframe_id = keyframe;
  fit.body_c = body_c;
  return fit;
}

PersonSighting sightingAt(int frame, double stamp, const Eigen::Vector3d& p_c, int keyframe = 0) {
  PersonSighting s;
  s.track_id = 7;
  s.frame_index = frame;
  s.timestamp = stamp;
  s.keyframe_id = keyframe;
  s.p_c = p_c;
  return s;
}

BodyTrackAssembler::Options noSmoothing() {
  BodyTrackAssembler::Options options;
  options.smoothing_sigma = 0;
  options.pose_smoothing_sigma = 0;
  return options;
}

// `body` moved so that its pelvis lies at `pelvis`.
BodyParameters withPelvisAt(const BodyParameters& body, const Eigen::Vector3d& pelvis) {
  BodyParameters moved = body;
  moved.translation = pelvis - model().restJoints(body.shape)[0];
  return moved;
}

// One person seen and fitted in each of `frames` frames 0.1 s apart by a camera that never moves
// (keyframe 0 at the origin): the fit's pelvis at pelvis(f), the eq. 2 centre at centre(f).
struct FittedEveryFrame {
  std::vector<PersonSighting> seen;
  std::vector<BodyTrackFit> fits;

  FittedEveryFrame(int frames, const std::function<Eigen::Vector3d(int)>& pelvis,
                   const std::function<Eigen::Vector3d(int)>& centre) {
    for (int f = 0; f < frames; ++f) {
      seen.push_back(sightingAt(f, 0.1 * f, centre(f)));
      fits.push_back(fitAt(f, 0.1 * f, withPelvisAt(personInCamera(), pelvis(f))));
    }
  }
  std::vector<BodyTrack> tracks(const BodyTrackAssembler::Options& options) const {
    return BodyTrackAssembler(model(), options).assemble(seen, fits, {{0, Eigen::Isometry3d::Identity()}}, CameraIntrinsics());
  }
};

// Eq. 4 with a known camera pose: the fitted body's joints in the world are T_w_c times its joints
// in the camera, with the keyframe's final (loop-corrected) pose, not the one tracked at the time.
TEST(BodyTrackAssembler, PlacesAFitByEq4WithTheFinalKeyframePose) {
  const BodyParameters body_c = personInCamera();
  const Eigen::Isometry3d T_w_k = cameraPose(0.6, Eigen::Vector3d(1, -2, 0.5));
  const Eigen::Isometry3d T_k_c = cameraPose(-0.2, Eigen::Vector3d(0.1, 0, 0.05));
  BodyTrackFit fit = fitAt(0, 10.0, body_c, 3);
  fit.T_k_c = T_k_c;
  PersonSighting seen = sightingAt(0, 10.0, Eigen::Vector3d(0.2, 0.1, 2.4), 3);
  seen.T_k_c = T_k_c;
  const BodyTrackAssembler assembler(model(), noSmoothing());
  const std::vector<BodyTrack> tracks = assembler.assemble({seen}, {fit}, {{3, T_w_k}}, CameraIntrinsics());
  ASSERT_EQ(tracks.size(), 1u);
  ASSERT_EQ(tracks[0].frames.size(), 1u);
  const BodyTrackFrame& frame = tracks[0].frames[0];
  EXPECT_TRUE(frame.fitted);
  const auto joints_c = model().posedJoints(body_c);
  const Eigen::Isometry3d T_w_c = T_w_k * T_k_c;
  for (int j = 0; j < kBodyJointCount; ++j) EXPECT_LT((frame.joints_w[j] - T_w_c * joints_c[j]).norm(), 1e-9) << j;
  // T_w_h: the root frame in the world, at the pelvis.
  EXPECT_LT((frame.T_w_h.translation() - T_w_c * joints_c[0]).norm(), 1e-9);
  const Eigen::Matrix3d R_root_c = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_LT((frame.T_w_h.linear() - T_w_c.linear() * R_root_c).norm(), 1e-9);
  // The track of humans.txt is the pelvis.
  const std::vector<HumanTrack> people = pelvisTracks(tracks);
  ASSERT_EQ(people.size(), 1u);
  EXPECT_LT((people[0].points[0].p_w - T_w_c * joints_c[0]).norm(), 1e-9);
}

// Between two fits (with no others beyond them) the pelvis moves linearly and the joints rotate
// halfway (slerp); before the
// first fit and after the last the body is the nearest fit's, moved with the eq. 2 centre, however
// far that fit is (the centre alone lies on the visible side of the body: a seated person's
// centre is a quarter metre above the pelvis). The placement by the visible centre, which differs
// where the body is cut by the image border, is tested in visible_centre_test.cpp.
TEST(BodyTrackAssembler, InterpolatesBetweenFitsAndPlacesTheRest) {
  BodyParameters a = personInCamera(), b = personInCamera();
  b.pose[1] = Eigen::Vector3d(0.2, 0, 0);
  b.translation += Eigen::Vector3d(0.3, 0, 0);
  const Eigen::Vector3d centre(0.2, 0.1, 2.4);
  std::vector<PersonSighting> seen;
  for (int f : {0, 3, 4, 5, 6, 80}) seen.push_back(sightingAt(f, 0.1 * f, centre + Eigen::Vector3d(0.01 * f, 0, 0)));
  BodyTrackAssembler::Options options = noSmoothing();
  options.visible_centre = false;
  const BodyTrackAssembler assembler(model(), options);
  const std::vector<BodyTrack> tracks =
      assembler.assemble(seen, {fitAt(4, 0.4, a), fitAt(6, 0.6, b)}, {{0, Eigen::Isometry3d::Identity()}},
                         CameraIntrinsics());
  ASSERT_EQ(tracks.size(), 1u);
  const std::vector<BodyTrackFrame>& frames = tracks[0].frames;
  ASSERT_EQ(frames.size(), 6u);
  EXPECT_FALSE(frames[0].fitted);
  EXPECT_TRUE(frames[2].fitted);
  EXPECT_FALSE(frames[3].fitted);
  EXPECT_TRUE(frames[4].fitted);
  // Frame 5, halfway: the pelvis halfway, the left hip's rotation halfway.
  EXPECT_LT((frames[3].pelvis_w - 0.5 * (frames[2].pelvis_w + frames[4].pelvis_w)).norm(), 1e-9);
  EXPECT_NEAR(frames[3].body_w.pose[1].x(), -0.1, 1e-9);
  // Frame 3, 0.1 s before the first fit: that fit's body, moved by the centre's motion (-1 cm).
  EXPECT_LT((frames[1].pelvis_w - (frames[2].pelvis_w + Eigen::Vector3d(-0.01, 0, 0))).norm(), 1e-9);
  // Frame 80, 7.4 s after the last fit: still that fit's body, moved by the centre's motion (+74 cm).
  EXPECT_LT((frames[5].pelvis_w - (frames[4].pelvis_w + Eigen::Vector3d(0.74, 0, 0))).norm(), 1e-9);
  EXPECT_NEAR(frames[5].body_w.pose[1].x(), 0.2, 1e-9);
  // One shape for the whole track: the mean of its fits.
  for (const BodyTrackFrame& f : frames) EXPECT_LT((f.body_w.shape - a.shape).norm(), 1e-12);
}

// A person walking a circle of 1 m radius at 1 m/s, fitted every 0.1 s but for a second: across
// the gap the pelvis follows the track's velocity on both sides (velocity_span, taken over 0.5 s, so
// a little behind the turn), within half of the 12 cm by which the straight line between the
// gap's two fits cuts the circle.
TEST(BodyTrackAssembler, FollowsTheTracksCurveAcrossAGapBetweenFits) {
  const auto on_circle = [](double t) { return Eigen::Vector3d(std::sin(t), 0.1, 3.0 - std::cos(t)); };
  const BodyParameters body = personInCamera();
  const Eigen::Vector3d rest_pelvis = model().restJoints(body.shape)[0];
  std::vector<PersonSighting> seen;
  std::vector<BodyTrackFit> fits;
  for (int f = 0; f <= 20; ++f) {
    seen.push_back(sightingAt(f, 0.1 * f, on_circle(0.1 * f)));
    if (f > 5 && f < 15) continue;
    BodyParameters fitted = body;
    fitted.translation = on_circle(0.1 * f) - rest_pelvis;
    fits.push_back(fitAt(f, 0.1 * f, fitted));
  }
  BodyTrackAssembler::Options options = noSmoothing();
  const auto middleError = [&](const BodyTrackAssembler::Options& o) {
    const std::vector<BodyTrack> tracks =
        BodyTrackAssembler(model(), o).assemble(seen, fits, {{0, Eigen::Isometry3d::Identity()}}, CameraIntrinsics());
    EXPECT_EQ(tracks.size(), 1u);
    EXPECT_FALSE(tracks[0].frames[10].fitted);
    return (tracks[0].frames[10].pelvis_w - on_circle(1.0)).norm();
  };
  EXPECT_LT(middleError(options), 0.5 * (1.0 - std::cos(0.5)));
  options.velocity_span = 0;
  EXPECT_NEAR(middleError(options), 1.0 - std::cos(0.5), 1e-6);
}

// A person walking at 1 m/s along x, fitted up to 1 s, then seen for 0.3 s more with their eq. 2
// centre stuck where the last fit was (the sliver of them still in view as they step behind
// someone): those frames move on with the track's velocity (max_extrapolation), not with the centre.
TEST(BodyTrackAssembler, MovesOnWithTheTrackAfterItsLastFit) {
  const auto on_line = [](double t) { return Eigen::Vector3d(t, 0.1, 3.0); };
  const BodyParameters body = personInCamera();
  const Eigen::Vector3d rest_pelvis = model().restJoints(body.shape)[0];
  std::vector<PersonSighting> seen;
  std::vector<BodyTrackFit> fits;
  for (int f = 0; f <= 13; ++f) {
    seen.push_back(sightingAt(f, 0.1 * f, on_line(std::min(0.1 * f, 1.0))));
    if (f > 10) continue;
    BodyParameters fitted = body;
    fitted.translation = on_line(0.1 * f) - rest_pelvis;
    fits.push_back(fitAt(f, 0.1 * f, fitted));
  }
  BodyTrackAssembler::Options options = noSmoothing();
  options.visible_centre = false;
  options.centre_sigma = 0;  // the extrapolation alone (the next test draws it towards the centre)
  const auto lastPelvis = [&](const BodyTrackAssembler::Options& o) {
    const std::vector<BodyTrack> tracks =
        BodyTrackAssembler(model(), o).assemble(seen, fits, {{0, Eigen::Isometry3d::Identity()}}, CameraIntrinsics());
    EXPECT_EQ(tracks.size(), 1u);
    EXPECT_FALSE(tracks[0].frames.back().fitted);
    return tracks[0].frames.back().pelvis_w;
  };
  EXPECT_LT((lastPelvis(options) - on_line(1.3)).norm(), 1e-9);
  options.max_extrapolation = 0.2;  // 0.3 s after the last fit: beyond it, placed by the centre
  EXPECT_LT((lastPelvis(options) - on_line(1.0)).norm(), 1e-9);
}

// A person standing still, fitted up to 1 s, who then walks off at 1 m/s along x with no more
// fits (their poses refused): the frames after the last fit follow the eq. 2 centre more the longer
// it has been (centre_sigma: the extrapolation, at a standstill, grows less certain as 1/2 a t^2),
// while a centre a metre off after 0.1 s (someone else's pixels) is not believed.
TEST(BodyTrackAssembler, AfterItsLastFitATrackIsDrawnTowardsItsCentreAsTimeGoesBy) {
  const Eigen::Vector3d still(0.0, 0.1, 3.0);
  const auto walked = [&](double t) { return Eigen::Vector3d(still + Eigen::Vector3d(std::max(0.0, t - 1.0), 0, 0)); };
  const BodyParameters body = withPelvisAt(personInCamera(), still);
  std::vector<PersonSighting> seen;
  std::vector<BodyTrackFit> fits;
  for (int f = 0; f <= 14; ++f) {
    seen.push_back(sightingAt(f, 0.1 * f, f == 11 ? Eigen::Vector3d(walked(1.1) + Eigen::Vector3d(1.0, 0, 0)) : walked(0.1 * f)));
    if (f <= 10) fits.push_back(fitAt(f, 0.1 * f, body));
  }
  BodyTrackAssembler::Options options = noSmoothing();
  options.visible_centre = false;
  options.hold_height = false;
  const auto pelvisAt = [&](const BodyTrackAssembler::Options& o, size_t frame) {
    const std::vector<BodyTrack> tracks =
        BodyTrackAssembler(model(), o).assemble(seen, fits, {{0, Eigen::Isometry3d::Identity()}}, CameraIntrinsics());
    EXPECT_EQ(tracks.size(), 1u);
    return tracks[0].frames.at(frame).pelvis_w;
  };
  // 0.4 s after the fit: the extrapolation's spread 1/2 x 2 x 0.16 = 0.16 m against the centre's
  // 0.1 m, so 0.0256 / 0.0356 of the way to the centre, 0.4 m away.
  const Eigen::Vector3d later = pelvisAt(options, 14);
  EXPECT_NEAR(later.x(), 0.4 * 0.0256 / 0.0356, 1e-6);
  EXPECT_NEAR((later - walked(1.4)).norm(), 0.4 * 0.01 / 0.0356, 1e-6);
  // 0.2 s after it: 0.04 m against 0.1 m, so 0.0016 / 0.0116 of the way to the centre, 0.2 m away.
  EXPECT_NEAR(pelvisAt(options, 12).x(), 0.2 * 0.0016 / 0.0116, 1e-6);
  // The centre a metre off at 0.1 s, beyond three spreads of both (0.3 m): the extrapolation.
  EXPECT_LT((pelvisAt(options, 11) - still).norm(), 1e-9);
  options.centre_sigma = 0;  // the extrapolation alone: the person stays where they stood
  EXPECT_LT((pelvisAt(options, 14) - still).norm(), 1e-9);
}

// The joints' rotations are smoothed over time: a knee whose fits jitter by +-0.1 rad around
// 0.3 rad from one frame to the next (30 fps) comes out within a few hundredths of 0.3 in the
// middle of the track, with its joints following the smoothed pose; the pelvis does not move, and
// a frame too far from the others to be averaged with them keeps its own pose.
TEST(BodyTrackAssembler, SmoothsTheJointRotationsOverTime) {
  std::vector<PersonSighting> seen;
  std::vector<BodyTrackFit> fits;
  const Eigen::Vector3d centre(0.2, 0.1, 2.4);
  for (int f = 0; f < 30; ++f) {
    BodyParameters body = personInCamera();
    body.pose[4] = Eigen::Vector3d(0.3 + (f % 2 ? 0.1 : -0.1), 0, 0);  // left knee
    const double stamp = f / 30.0 + (f == 29 ? 5.0 : 0.0);               // the last one 5 s later
    seen.push_back(sightingAt(f, stamp, centre));
    fits.push_back(fitAt(f, stamp, body));
  }
  BodyTrackAssembler::Options smooth = noSmoothing();
  smooth.pose_smoothing_sigma = 0.1;
  const std::map<int, Eigen::Isometry3d> keyframes{{0, Eigen::Isometry3d::Identity()}};
  const std::vector<BodyTrack> raw = BodyTrackAssembler(model(), noSmoothing()).assemble(seen, fits, keyframes, {});
  const std::vector<BodyTrack> out = BodyTrackAssembler(model(), smooth).assemble(seen, fits, keyframes, {});
  ASSERT_EQ(out.size(), 1u);
  ASSERT_EQ(out[0].frames.size(), 30u);
  for (int f = 10; f < 20; ++f) {
    const BodyTrackFrame& frame = out[0].frames[f];
    EXPECT_NEAR(raw[0].frames[f].body_w.pose[4].norm(), f % 2 ? 0.4 : 0.2, 1e-9);
    EXPECT_NEAR(frame.body_w.pose[4].norm(), 0.3, 0.02) << f;
    EXPECT_LT((frame.pelvis_w - raw[0].frames[f].pelvis_w).norm(), 1e-9);
    const auto joints = model().posedJoints(frame.body_w);
    for (int j = 0; j < kBodyJointCount; ++j) EXPECT_LT((frame.joints_w[j] - joints[j]).norm(), 1e-9);
  }
  EXPECT_NEAR(out[0].frames[29].body_w.pose[4].norm(), 0.4, 1e-9);
}

// A person never fitted (keypoints too few in every frame): a standing body with its pelvis at the
// eq. 2 centre, facing the camera as eq. 4's human frame does.
TEST(BodyTrackAssembler, APersonWithoutFitsStandsAtTheCentre) {
  const Eigen::Vector3d centre(0.2, 0.1, 2.4);
  const BodyTrackAssembler assembler(model(), noSmoothing());
  const std::vector<BodyTrack> tracks =
      assembler.assemble({sightingAt(0, 0.0, centre), sightingAt(1, 0.1, centre)}, {},
                         {{0, Eigen::Isometry3d::Identity()}}, CameraIntrinsics());
  ASSERT_EQ(tracks.size(), 1u);
  ASSERT_EQ(tracks[0].frames.size(), 2u);
  for (const BodyTrackFrame& frame : tracks[0].frames) {
    EXPECT_FALSE(frame.fitted);
    EXPECT_LT((frame.pelvis_w - centre).norm(), 1e-9);
    const Eigen::Matrix3d R_x180 = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
    EXPECT_LT((frame.T_w_h.linear() - R_x180).norm(), 1e-9);
  }
}

// A fit far off where the track's other fits lie (relative to the eq. 2 centre) is dropped.
TEST(BodyTrackAssembler, DropsAFitFarFromTheOthers) {
  const BodyParameters body = personInCamera();
  BodyParameters wrong = body;
  wrong.translation += Eigen::Vector3d(0, 0, 0.8);  // 80 cm behind the person
  std::vector<PersonSighting> seen;
  std::vector<BodyTrackFit> fits;
  for (int f = 0; f < 5; ++f) {
    seen.push_back(sightingAt(f, 0.1 * f, Eigen::Vector3d(0.2, 0.1, 2.4)));
    fits.push_back(fitAt(f, 0.1 * f, f == 2 ? wrong : body));
  }
  const BodyTrackAssembler assembler(model(), noSmoothing());
  const std::vector<BodyTrack> tracks =
      assembler.assemble(seen, fits, {{0, Eigen::Isometry3d::Identity()}}, CameraIntrinsics());
  ASSERT_EQ(tracks[0].frames.size(), 5u);
  EXPECT_EQ(tracks[0].fits, 4);
  EXPECT_FALSE(tracks[0].frames[2].fitted);
  EXPECT_LT((tracks[0].frames[2].pelvis_w - tracks[0].frames[1].pelvis_w).norm(), 1e-9);
}

// A person walking at 1 m/s, fitted every 0.1 s; one fit lies 40 cm off their path, and its eq. 2
// centre moved with it (the wrong pixels: the offset rule keeps it). The path rule drops it: its
// frame lies on the line between its neighbours. Switched off (0), the fit stays.
TEST(BodyTrackAssembler, DropsAFitThatLeavesThePathOfItsNeighbours) {
  const auto on_line = [](double t) { return Eigen::Vector3d(t, 0.1, 3.0); };
  const Eigen::Vector3d off_path(0, 0, 0.4);
  const auto pelvis = [&](int f) { return Eigen::Vector3d(on_line(0.1 * f) + (f == 5 ? off_path : Eigen::Vector3d::Zero())); };
  const FittedEveryFrame person(10, pelvis, pelvis);
  BodyTrackAssembler::Options options = noSmoothing();
  const std::vector<BodyTrack> tracks = person.tracks(options);
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_EQ(tracks[0].fits, 9);
  EXPECT_FALSE(tracks[0].frames[5].fitted);
  EXPECT_LT((tracks[0].frames[5].pelvis_w - on_line(0.5)).norm(), 1e-9);
  options.max_path_deviation = 0;
  const std::vector<BodyTrack> kept = person.tracks(options);
  EXPECT_EQ(kept[0].fits, 10);
  EXPECT_LT((kept[0].frames[5].pelvis_w - on_line(0.5) - off_path).norm(), 1e-9);
}

// A track whose fits jump by 1.5 m from one to the next (another person took it over): the fits on
// either side of the jump are no path to judge by, and none is dropped.
TEST(BodyTrackAssembler, KeepsTheFitsOnBothSidesOfAJump) {
  const auto pelvis = [](int f) { return Eigen::Vector3d(f < 5 ? 0.0 : 1.5, 0.1, 3.0); };
  const std::vector<BodyTrack> tracks = FittedEveryFrame(10, pelvis, pelvis).tracks(noSmoothing());
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_EQ(tracks[0].fits, 10);
}

// A seated person fitted every 0.1 s for 5 s; for 2.5 s someone passing in front joins their mask,
// and their eq. 2 centre lies 40 cm aside while the fits stay on them. The offset rule alone drops
// those fits (the gap is longer than max_gap, so its frames follow the wrong centre); the fits lie
// on the path of the fits kept around them and are kept. With the path rule off they are dropped.
TEST(BodyTrackAssembler, KeepsFitsOnThePathWhenTheirCentresAreWrong) {
  const Eigen::Vector3d pelvis(0.2, 0.1, 3.0);
  const Eigen::Vector3d aside(0.4, 0, 0);
  const auto centre = [&](int f) { return Eigen::Vector3d(pelvis + (f >= 10 && f < 35 ? aside : Eigen::Vector3d::Zero())); };
  const FittedEveryFrame person(50, [&](int) { return pelvis; }, centre);
  BodyTrackAssembler::Options options = noSmoothing();
  const std::vector<BodyTrack> tracks = person.tracks(options);
  ASSERT_EQ(tracks.size(), 1u);
  EXPECT_EQ(tracks[0].fits, 50);
  EXPECT_TRUE(tracks[0].frames[22].fitted);
  EXPECT_LT((tracks[0].frames[22].pelvis_w - pelvis).norm(), 1e-9);
  options.max_path_deviation = 0;
  const std::vector<BodyTrack> dropped = person.tracks(options);
  EXPECT_EQ(dropped[0].fits, 25);
  EXPECT_FALSE(dropped[0].frames[22].fitted);
  EXPECT_GT((dropped[0].frames[22].pelvis_w - pelvis).norm(), 0.3);
}

// humans.json holds what the assembler made; the joints follow from pose, shape and pelvis
// within 1 mm (the file's 6 decimals).
TEST(BodyTracksJson, WritesAndReadsBackAndTheJointsFollowFromPoseAndShape) {
  std::vector<PersonSighting> seen;
  std::vector<BodyTrackFit> fits;
  for (int f = 0; f < 4; ++f) {
    BodyParameters body = personInCamera();
    body.pose[4] = Eigen::Vector3d(0.3 * f, 0, 0);
    seen.push_back(sightingAt(f, 1700000000.0 + f / 30.0, Eigen::Vector3d(0.2, 0.1, 2.4)));
    if (f != 2) fits.push_back(fitAt(f, seen.back().timestamp, body));
  }
  const std::vector<BodyTrack> tracks =
      BodyTrackAssembler(model(), BodyTrackAssembler::Options())
          .assemble(seen, fits, {{0, cameraPose(0.3, Eigen::Vector3d(0.5, 0.2, -1))}},
                    CameraIntrinsics());
  const std::string path = testing::TempDir() + "pf2_humans.json";
  writeBodyTracksJson(path, tracks);
  const std::vector<BodyTrack> read = readBodyTracksJson(path);
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(read[0].id, 7);
  ASSERT_EQ(read[0].frames.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    const BodyTrackFrame& f = read[0].frames[i];
    EXPECT_NEAR(f.timestamp, seen[i].timestamp, 1e-6);
    EXPECT_EQ(f.fitted, i != 2);
    EXPECT_LT((f.T_w_h.matrix() - tracks[0].frames[i].T_w_h.matrix()).cwiseAbs().maxCoeff(), 1e-6);
    // Recomputed: the model with the file's pose, shape and translation.
    const auto posed = model().posedJoints(f.body_w);
    for (int j = 0; j < kBodyJointCount; ++j) {
      EXPECT_LT((posed[j] - f.joints_w[j]).norm(), 1e-3) << "frame " << i << " joint " << j;
    }
    EXPECT_LT((f.joints_w[0] - f.pelvis_w).norm(), 1e-6);
  }
}

TEST(BodyTracksJson, RefusesBrokenFilesNamingWhatIsWrong) {
  const std::string path = testing::TempDir() + "pf2_broken_humans.json";
  const auto refuses = [&](const std::string& text, const std::string& expected) {
    FILE* f = std::fopen(path.c_str(), "w");
    std::fputs(text.c_str(), f);
    std::fclose(f);
    try {
      readBodyTracksJson(path);
      ADD_FAILURE() << "accepted " << text;
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  refuses("{\"tracks\": [", "not a JSON document");
  refuses("[1, 2]", "expected {\"tracks\"");
  refuses("{\"tracks\": [{\"id\": 1, \"frames\": [{\"timestamp\": 1}]}]}", "\"T_w_h\"");
  refuses("{\"tracks\": [{\"id\": 1, \"frames\": [{\"timestamp\": 1, \"T_w_h\": [1, 2]}]}]}", "list of 16 numbers");
}

// The fitter on a person whose keypoints are their own joints projected into the camera: one
// valid fit per fit_every frames, near the true body; a full queue drops observations and counts them.
TEST(BodyTrackFitter, FitsEveryNthFrameAndCountsWhatItDrops) {
  const CameraIntrinsics K = CameraIntrinsics::tumFreiburg3();
  const BodyParameters truth = personInCamera();
  const auto joints = model().posedJoints(truth);
  BodyObservation observation;
  observation.track_id = 1;
  observation.intrinsics = K;
  observation.T_w_c = Eigen::Isometry3d::Identity();
  observation.keyframe_id = 0;
  const auto keypoints = BodyFitter(model()).keypointPoints(truth);
  for (int k = 0; k < kCocoKeypointCount; ++k) {
    if (kCocoToBodyJoint[k].joint < 0) continue;
    const Eigen::Vector3d& p = keypoints[k];
    observation.keypoints[k] = {K.fx * p.x() / p.z() + K.cx, K.fy * p.y() / p.z() + K.cy, 0.9};
  }
  BodyTrackFitter::Options options;
  options.fit_every = 3;
  options.asynchronous = false;
  BodyTrackFitter fitter(model(), options);
  int offered = 0;
  for (int frame = 0; frame < 9; ++frame) {
    if (!fitter.wants(1, frame)) continue;
    BodyObservation o = observation;
    o.frame_index = frame;
    o.timestamp = frame / 30.0;
    EXPECT_TRUE(fitter.offer(o));
    ++offered;
  }
  EXPECT_EQ(offered, 3);
  const std::vector<BodyTrackFit> fits = fitter.finish();
  ASSERT_EQ(fits.size(), 3u);
  for (const BodyTrackFit& fit : fits) {
    const auto fitted = model().posedJoints(fit.body_c);
    // Keypoints alone fix the body up to its distance: the shoulders' direction is right.
    const Eigen::Vector3d shoulders = (fitted[16] - fitted[17]).normalized();
    EXPECT_GT(shoulders.dot((joints[16] - joints[17]).normalized()), 0.95) << fit.frame_index;
  }
  EXPECT_EQ(fits[1].frame_index, 3);
  EXPECT_THROW(fitter.offer(observation), Error);

  // Asynchronous with a queue of one: offers made faster than fits drop, and are counted.
  options.asynchronous = true;
  options.queue_capacity = 1;
  options.fit_every = 1;
  BodyTrackFitter busy(model(), options);
  int accepted = 0;
  for (int frame = 0; frame < 20; ++frame) {
    BodyObservation o = observation;
    o.frame_index = frame;
    o.timestamp = frame / 30.0;
    accepted += busy.offer(o) ? 1 : 0;
  }
  const std::vector<BodyTrackFit> busy_fits = busy.finish();
  EXPECT_EQ(busy.offered(), 20);
  EXPECT_EQ(busy.dropped(), 20 - accepted);
  EXPECT_GT(busy.dropped(), 0);
  EXPECT_EQ(static_cast<int>(busy_fits.size()), accepted);
  // Every fit that ran is timed once; without a refiner nothing is timed as "refine".
  EXPECT_EQ(busy.stats().summary("fit").count, accepted);
  EXPECT_GT(busy.stats().summary("fit").median_ms, 0.0);
  EXPECT_EQ(busy.stats().summary("refine").count, 0);
}

// One observation of the person personInCamera() moved `shift` metres away from the camera: their
// projected keypoints and a plate of depth points at their pelvis's depth behind their keypoints.
BodyObservation observationAt(double shift, int frame) {
  const CameraIntrinsics K = CameraIntrinsics::tumFreiburg3();
  BodyParameters body = personInCamera();
  body.translation.z() += shift;
  const auto points = BodyFitter(model()).keypointPoints(body);
  BodyObservation o;
  o.track_id = 1;
  o.frame_index = frame;
  o.timestamp = frame / 30.0;
  o.intrinsics = K;
  o.keyframe_id = 0;
  std::vector<cv::Point2f> pixels;
  for (int k = 0; k < kCocoKeypointCount; ++k) {
    if (kCocoToBodyJoint[k].joint < 0) continue;
    const Eigen::Vector3d& p = points[k];
    o.keypoints[k] = {K.fx * p.x() / p.z() + K.cx, K.fy * p.y() / p.z() + K.cy, 0.9};
    pixels.emplace_back(static_cast<float>(o.keypoints[k].u), static_cast<float>(o.keypoints[k].v));
  }
  o.depth_area = cv::boundingRect(pixels) & cv::Rect(0, 0, K.width, K.height);
  const double pelvis_depth = (body.translation + model().restJoints(body.shape)[0]).z();
  o.depth = cv::Mat(o.depth_area.size(), CV_32F, cv::Scalar(pelvis_depth));
  return o;
}

// The cost of the fit of `second` after a fit of `first` on the same track.
double costAfter(const BodyObservation& first, const BodyObservation& second, double max_start_depth_gap) {
  BodyTrackFitter::Options options;
  options.asynchronous = false;
  options.fit_every = 1;
  options.max_start_depth_gap = max_start_depth_gap;
  BodyTrackFitter fitter(model(), options);
  fitter.offer(first);
  fitter.offer(second);
  const std::vector<BodyTrackFit> fits = fitter.finish();
  EXPECT_EQ(fits.size(), 2u);
  return fits.empty() ? 0.0 : fits.back().cost;
}

// A track's previous fit is the next one's start only where its pelvis lies within
// max_start_depth_gap of the person's measured depth: a track that jumped to someone else 1 m
// farther starts afresh (its fit is the fit of a new track), one that moved 5 cm starts warm (the
// temporal term towards the start adds to the cost).
TEST(BodyTrackFitter, AStartFarFromThePersonsDepthIsNotUsed) {
  BodyTrackFitter::Options cold_options;
  cold_options.asynchronous = false;
  const BodyObservation here = observationAt(0.0, 0), far = observationAt(1.0, 1), near = observationAt(0.05, 1);
  const auto coldCost = [&](const BodyObservation& o) {
    BodyTrackFitter fresh(model(), cold_options);
    fresh.offer(o);
    return fresh.finish().at(0).cost;
  };
  EXPECT_NEAR(costAfter(here, far, 0.3), coldCost(far), 1e-9);
  EXPECT_GT(std::abs(costAfter(here, far, 0.0) - coldCost(far)), 1e-6);  // no check: warm
  EXPECT_GT(std::abs(costAfter(here, near, 0.3) - coldCost(near)), 1e-6);
}

// The longest body segment of a pose is measured on the plane at a depth: the person of
// personInCamera() at 2.5 m measures a real body's thigh or torso side there, a fifth of it at
// 0.5 m; head keypoints and unsure ends do not count.
TEST(LongestBodySegment, MeasuresThePoseOnThePlaneAtItsDepth) {
  const BodyObservation o = observationAt(0.0, 0);
  const double at_its_depth = longestBodySegment(o.keypoints, 2.5, o.intrinsics, 0.1);
  EXPECT_GT(at_its_depth, 0.35);
  EXPECT_LT(at_its_depth, 0.6);
  EXPECT_NEAR(longestBodySegment(o.keypoints, 0.5, o.intrinsics, 0.1), at_its_depth / 5.0, 1e-9);
  std::array<BodyKeypoint, kCocoKeypointCount> sides{};
  sides[5] = {340, 200, 0.9};  // left shoulder
  sides[11] = {335, 280, 0.9};  // left hip, 80 px below
  sides[0] = {340, 100, 0.9};  // the nose: no segment
  EXPECT_NEAR(longestBodySegment(sides, 2.0, o.intrinsics, 0.1),
              std::hypot(5 * 2.0 / o.intrinsics.fx, 80 * 2.0 / o.intrinsics.fy), 1e-12);
  sides[11].confidence = 0.05;
  EXPECT_EQ(longestBodySegment(sides, 2.0, o.intrinsics, 0.1), 0.0);
}

// How many fits one observation gives with these options.
size_t fitCount(const BodyObservation& o, const BodyTrackFitter::Options& options) {
  BodyTrackFitter fitter(model(), options);
  fitter.offer(o);
  return fitter.finish().size();
}

// A near person's mask that took the pose of someone farther away (seen beside or through them):
// the pose measures a fifth of a body at the near person's depth, and is not fitted; the same
// pose at its own depth, or with the check off, is.
TEST(BodyTrackFitter, APoseFarSmallerThanABodyAtThePersonsDepthIsNotFitted) {
  BodyTrackFitter::Options options;
  options.asynchronous = false;
  options.min_torso_side = 0.0;  // this check alone (the torso's sides would also refuse this pose)
  ASSERT_GT(options.min_pose_size, 0.0);
  BodyObservation near = observationAt(0.0, 0);
  EXPECT_EQ(fitCount(near, options), 1u);
  near.depth.setTo(0.5);  // a person five times nearer than the pose (its pelvis lies at 2.5 m)
  EXPECT_LT(longestBodySegment(near.keypoints, 0.5, near.intrinsics, 0.1), options.min_pose_size);
  EXPECT_EQ(fitCount(near, options), 0u);
  options.min_pose_size = 0.0;
  EXPECT_EQ(fitCount(near, options), 1u);
}

// A torso side is measured only where both its keypoints are sure and in full view: the person of
// personInCamera() at 2.5 m measures a real body's side there; a hip in the edge band, or unsure,
// leaves only the other side, and with neither there is nothing to measure.
TEST(ShortestTorsoSide, MeasuresOnlySidesInFullView) {
  const BodyObservation o = observationAt(0.0, 0);
  const CameraIntrinsics& K = o.intrinsics;
  const double at_its_depth = shortestTorsoSide(o.keypoints, 2.5, K, 0.1, 16.0);
  EXPECT_GT(at_its_depth, 0.35);
  EXPECT_LT(at_its_depth, 0.55);
  EXPECT_NEAR(shortestTorsoSide(o.keypoints, 1.25, K, 0.1, 16.0), at_its_depth / 2.0, 1e-9);
  std::array<BodyKeypoint, kCocoKeypointCount> sides{};
  sides[5] = {300, 200, 0.9};   // left shoulder
  sides[11] = {310, 300, 0.9};  // left hip, 100 px below
  sides[6] = {250, 200, 0.9};   // right shoulder
  sides[12] = {255, 250, 0.9};  // right hip, 50 px below: the shorter side
  EXPECT_NEAR(shortestTorsoSide(sides, 2.0, K, 0.1, 16.0), std::hypot(5 * 2.0 / K.fx, 50 * 2.0 / K.fy), 1e-12);
  sides[12].v = K.height - 10;  // in the bottom edge band: that side is not measured
  EXPECT_NEAR(shortestTorsoSide(sides, 2.0, K, 0.1, 16.0), std::hypot(10 * 2.0 / K.fx, 100 * 2.0 / K.fy), 1e-12);
  sides[11].confidence = 0.05;
  EXPECT_EQ(shortestTorsoSide(sides, 2.0, K, 0.1, 16.0), 0.0);
}

// A whole body's keypoints squeezed into the part in view of a person close to the lens: the pose
// measures half a body at the person's depth, enough for min_pose_size but not for the torso's
// sides, and is not fitted; with the check off it is, and so is the same pose with its hips at the
// image's bottom edge (a person cut there, whose sides are not measured).
TEST(BodyTrackFitter, APoseSqueezedToHalfABodyAtThePersonsDepthIsNotFitted) {
  BodyTrackFitter::Options options;
  options.asynchronous = false;
  ASSERT_GT(options.min_torso_side, 0.0);
  BodyObservation squeezed = observationAt(0.0, 0);
  squeezed.depth.setTo(1.25);  // twice as near as the pose's own depth
  ASSERT_GT(longestBodySegment(squeezed.keypoints, 1.25, squeezed.intrinsics, 0.1), options.min_pose_size);
  ASSERT_LT(shortestTorsoSide(squeezed.keypoints, 1.25, squeezed.intrinsics, 0.1, 16.0), options.min_torso_side);
  EXPECT_EQ(fitCount(squeezed, options), 0u);
  BodyTrackFitter::Options unchecked = options;
  unchecked.min_torso_side = 0.0;
  EXPECT_EQ(fitCount(squeezed, unchecked), 1u);
  BodyObservation cut = squeezed;
  for (const int hip : {11, 12}) cut.keypoints[hip].v = squeezed.intrinsics.height - 5;
  EXPECT_EQ(fitCount(cut, options), 1u);
}

// Keypoint refinement: the hook gets the observation's colour, the person's box and keypoints in
// that colour's pixels, and the keypoints it gives back (in the same pixels) are what is fitted,
// moved back into the frame's pixels.
TEST(BodyTrackFitter, FitsTheRefinedKeypointsInTheFramesPixels) {
  const CameraIntrinsics K = CameraIntrinsics::tumFreiburg3();
  const BodyParameters truth = personInCamera();
  const auto points = BodyFitter(model()).keypointPoints(truth);
  std::array<BodyKeypoint, kCocoKeypointCount> true_keypoints{};
  for (int k = 0; k < kCocoKeypointCount; ++k) {
    if (kCocoToBodyJoint[k].joint < 0) continue;
    const Eigen::Vector3d& p = points[k];
    true_keypoints[k] = {K.fx * p.x() / p.z() + K.cx, K.fy * p.y() / p.z() + K.cy, 0.9};
  }
  BodyObservation observation;
  observation.track_id = 1;
  observation.intrinsics = K;
  observation.keypoints = true_keypoints;
  for (BodyKeypoint& k : observation.keypoints) k.u += 40;  // the whole-frame pass, 40 px off
  observation.colour = cv::Mat(300, 200, CV_8UC3, cv::Scalar::all(0));
  observation.colour_origin = {150, 60};
  observation.box = {200, 100, 80, 200};
  const cv::Point2d origin(150, 60);

  BodyTrackFitter::Options options;
  options.asynchronous = false;
  int calls = 0;
  options.refine_keypoints = [&](const cv::Mat& colour, const cv::Rect2f& box,
                                 std::array<BodyKeypoint, kCocoKeypointCount>* keypoints) {
    ++calls;
    EXPECT_EQ(colour.size(), cv::Size(200, 300));
    EXPECT_EQ(box, cv::Rect2f(50, 40, 80, 200));
    EXPECT_DOUBLE_EQ((*keypoints)[5].u, observation.keypoints[5].u - origin.x);
    for (int k = 0; k < kCocoKeypointCount; ++k) {
      (*keypoints)[k] = {true_keypoints[k].u - origin.x, true_keypoints[k].v - origin.y, true_keypoints[k].confidence};
    }
    return true;
  };
  // Median pixel distance of a fit's keypoints to the true ones.
  auto pixelError = [&](const BodyTrackFit& fit) {
    const auto fitted = BodyFitter(model()).keypointPoints(fit.body_c);
    std::vector<double> d;
    for (int k = 0; k < kCocoKeypointCount; ++k) {
      if (kCocoToBodyJoint[k].joint < 0) continue;
      const Eigen::Vector3d& p = fitted[k];
      d.push_back(std::hypot(K.fx * p.x() / p.z() + K.cx - true_keypoints[k].u,
                             K.fy * p.y() / p.z() + K.cy - true_keypoints[k].v));
    }
    return upperMedian(&d);
  };
  BodyTrackFitter refined(model(), options);
  refined.offer(observation);
  const std::vector<BodyTrackFit> refined_fits = refined.finish();
  ASSERT_EQ(refined_fits.size(), 1u);
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(refined.stats().summary("refine").count, 1);
  EXPECT_LT(pixelError(refined_fits[0]), 3.0);

  options.refine_keypoints = nullptr;
  BodyTrackFitter plain(model(), options);
  plain.offer(observation);
  const std::vector<BodyTrackFit> plain_fits = plain.finish();
  ASSERT_EQ(plain_fits.size(), 1u);
  EXPECT_GT(pixelError(plain_fits[0]), 30.0);
}

}  // namespace
}  // namespace pf2
