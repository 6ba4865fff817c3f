#include "pf2/eval/human_metrics.h"

#include <cmath>

#include <gtest/gtest.h>

namespace pf2 {
namespace {

constexpr double kT0 = 100.0;

HumanTrack walk(int id, int first, int last, const Eigen::Vector3d& start, const Eigen::Vector3d& step) {
  HumanTrack track;
  track.id = id;
  for (int i = first; i <= last; ++i) track.points.push_back({kT0 + i / 30.0, start + step * i});
  return track;
}

HumanTrack shifted(HumanTrack track, int id, const Eigen::Vector3d& offset, double time_shift = 0.0) {
  track.id = id;
  for (HumanTrackPoint& point : track.points) {
    point.p_w += offset;
    point.timestamp += time_shift;
  }
  return track;
}

TEST(HumanMetrics, OneSwitchOneMissedFrameAndAConstantOffset) {
  // Person 1 walks 8 frames along x. Track 7 follows frames 0-2 at +10 cm in x, nothing in frame
  // 3, track 9 follows frames 4-7 at +10 cm: 7 of 8 matched, one switch (7 -> 9), one
  // fragmentation (the gap), every error 0.1 m, none once the offset is taken off.
  const HumanTrack truth = walk(1, 0, 7, {0, 0, 1}, {0.04, 0, 0});
  HumanTrack first = truth, second = truth;
  first.points.assign(truth.points.begin(), truth.points.begin() + 3);
  second.points.assign(truth.points.begin() + 4, truth.points.end());
  // Stamps 5 ms late: within the 20 ms association window.
  const std::vector<HumanTrack> estimate{shifted(first, 7, {0.1, 0, 0}, 0.005),
                                         shifted(second, 9, {0.1, 0, 0}, 0.005)};
  const HumanMetrics m = evaluateHumanTracks({truth}, estimate);
  EXPECT_EQ(m.frames, 8);
  EXPECT_EQ(m.matched, 7);
  EXPECT_DOUBLE_EQ(m.recall, 7.0 / 8.0);
  EXPECT_EQ(m.id_switches, 1);
  EXPECT_EQ(m.fragmentations, 1);
  EXPECT_EQ(m.tracks, 2);
  EXPECT_EQ(m.estimates, 7);
  EXPECT_EQ(m.unmatched_estimates, 0);
  ASSERT_EQ(m.people.size(), 1u);
  EXPECT_EQ(m.people[0].track, 9);  // 4 frames against 3
  EXPECT_NEAR(m.error.rmse, 0.1, 1e-12);
  EXPECT_NEAR(m.error.median, 0.1, 1e-12);
  EXPECT_TRUE(m.people[0].mean_offset.isApprox(Eigen::Vector3d(0.1, 0, 0), 1e-12));
  EXPECT_NEAR(m.error_without_offset.max, 0.0, 1e-12);
}

TEST(HumanMetrics, OffsetsScatterAndFarOrLateEstimates) {
  // Person 2 is followed by track 1 at offsets alternating +0.1 / +0.3 m in z: errors 0.1 and
  // 0.3 (RMSE sqrt(0.05)), mean offset 0.2, 0.1 m each without it.
  const HumanTrack truth = walk(2, 0, 5, {1, 1, 1}, {0, 0.04, 0});
  HumanTrack track = truth;
  track.id = 1;
  for (size_t i = 0; i < track.points.size(); ++i) track.points[i].p_w.z() += i % 2 == 0 ? 0.1 : 0.3;
  // Person 3 stands still; track 2 is 0.6 m away (beyond 0.5 m: no match), track 3 is right but
  // its stamps lie 1 s after the last frame (more than 20 ms from any frame: no frame).
  const HumanTrack still = walk(3, 0, 5, {3, 0, 1}, {0, 0, 0});
  const HumanTrack far = shifted(still, 2, {0.6, 0, 0});
  const HumanTrack late = shifted(still, 3, {0, 0, 0}, 1.0);
  const HumanMetrics m = evaluateHumanTracks({truth, still}, {track, far, late});
  EXPECT_EQ(m.frames, 12);
  EXPECT_EQ(m.matched, 6);
  EXPECT_EQ(m.unmatched_estimates, 12);
  EXPECT_EQ(m.id_switches, 0);
  EXPECT_EQ(m.fragmentations, 0);
  ASSERT_EQ(m.people.size(), 2u);
  EXPECT_EQ(m.people[0].gt_id, 2);
  EXPECT_EQ(m.people[0].track, 1);
  EXPECT_NEAR(m.people[0].error.rmse, std::sqrt(0.05), 1e-12);
  EXPECT_NEAR(m.people[0].error.median, 0.2, 1e-12);
  EXPECT_NEAR(m.people[0].mean_offset.z(), 0.2, 1e-12);
  EXPECT_NEAR(m.people[0].error_without_offset.rmse, 0.1, 1e-12);
  EXPECT_EQ(m.people[1].matched, 0);
  EXPECT_EQ(m.people[1].track, -1);
}

TEST(HumanMetrics, OptimalAssignmentBetweenTwoPeople) {
  // Two people 0.4 m apart, estimates 0.05 m and 0.3 m beside them (both within 0.5 m): the
  // minimum total distance gives each person their own track.
  const HumanTrack a = walk(1, 0, 2, {0, 0, 1}, {0, 0, 0});
  const HumanTrack b = walk(2, 0, 2, {0.4, 0, 1}, {0, 0, 0});
  const HumanMetrics m = evaluateHumanTracks({a, b}, {shifted(a, 5, {0.05, 0, 0}), shifted(b, 6, {0.3, 0, 0})});
  EXPECT_EQ(m.matched, 6);
  EXPECT_EQ(m.id_switches, 0);
  EXPECT_EQ(m.people[0].track, 5);
  EXPECT_EQ(m.people[1].track, 6);
  EXPECT_NEAR(m.people[0].error.max, 0.05, 1e-12);
  EXPECT_NEAR(m.people[1].error.max, 0.3, 1e-12);
}

TEST(HumanMetrics, APersonKeepsTheirTrackWhileItStaysNearAsClearMotDefines) {
  // Two people walk through each other along x (frames 0-4), each followed by a track. In frames 2
  // and 3, where the people are 2-20 cm apart, each track lies nearer the other person (in frame
  // 3 on them): matching by minimum distance alone would switch both twice. Person 1 keeps track 5
  // and person 2 track 6 while those lie within 0.5 m of them: no switch.
  HumanTrack a, b, ea, eb;
  a.id = 1, b.id = 2, ea.id = 5, eb.id = 6;
  const double ax[] = {0.0, 0.4, 0.50, 0.60, 1.0}, bx[] = {1.0, 0.6, 0.52, 0.40, 0.0};
  const double eax[] = {0.0, 0.4, 0.53, 0.42, 1.0}, ebx[] = {1.0, 0.6, 0.49, 0.58, 0.0};
  for (int i = 0; i < 5; ++i) {
    const double t = kT0 + i / 30.0;
    a.points.push_back({t, {ax[i], 0, 1}});
    b.points.push_back({t, {bx[i], 0, 1}});
    ea.points.push_back({t, {eax[i], 0, 1}});
    eb.points.push_back({t, {ebx[i], 0, 1}});
  }
  const HumanMetrics m = evaluateHumanTracks({a, b}, {ea, eb});
  EXPECT_EQ(m.matched, 10);
  EXPECT_EQ(m.id_switches, 0);
  EXPECT_EQ(m.people[0].track, 5);
  EXPECT_NEAR(m.people[0].error.max, 0.18, 1e-12);  // frame 3: track 5 at 0.42, person 1 at 0.60

  // A track that takes over the other person for good is a switch: track 5 jumps to person 2
  // (1 m from person 1) in frame 4, track 6 ends there.
  ea.points[4].p_w.x() = 0.0;
  eb.points.pop_back();
  const HumanMetrics swapped = evaluateHumanTracks({a, b}, {ea, eb});
  EXPECT_EQ(swapped.people[1].id_switches, 1);  // 6 -> 5
  EXPECT_EQ(swapped.people[0].matched, 4);      // nobody near person 1 in frame 4
}

}  // namespace
}  // namespace pf2
