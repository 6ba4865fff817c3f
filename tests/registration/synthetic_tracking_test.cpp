// Tracking on pf2_synth frames with people: removing them from depth (ground-truth masks, as the
// Dual-BBox filter would) keeps the trajectory at millimetres; leaving them in does not.
#include <gtest/gtest.h>

#include "pf2/eval/trajectory_metrics.h"
#include "pf2/registration/tracker.h"
#include "pf2/synth/synthetic_sequence.h"

namespace pf2 {
namespace {

TEST(SyntheticTracking, RemovingPeopleKeepsTheTrajectory) {
  SyntheticSequence::Options options;
  options.frames = 30;
  options.people = 3;
  options.camera = CameraMotion::kXyz;
  options.intrinsics = CameraIntrinsics::tumFreiburg3().scaled(0.5);  // cheaper to render
  const SyntheticSequence sequence(options);

  Tracker::Options tracker_options;
  tracker_options.asynchronous_backend = false;
  Tracker removed(tracker_options), kept(tracker_options);
  Trajectory truth, with_removal, without_removal;
  int person_pixels = 0;
  for (size_t i = 0; i < sequence.size(); ++i) {
    FrameGroundTruth gt;
    const Frame frame = sequence.frame(i, &gt);
    const cv::Mat mask = gt.labels > 0;
    person_pixels += cv::countNonZero(mask);
    Frame clean = frame;
    clean.depth = frame.depth.clone();
    clean.depth.setTo(0.0f, mask);
    truth.push_back({frame.timestamp, gt.T_w_c});
    const TrackResult a = removed.track(clean, mask);
    ASSERT_NE(a.status, TrackStatus::kLost) << "frame " << i;
    with_removal.push_back({frame.timestamp, a.T_w_c});
    const TrackResult b = kept.track(frame);
    if (b.status != TrackStatus::kLost) without_removal.push_back({frame.timestamp, b.T_w_c});
  }
  ASSERT_GT(person_pixels, 0) << "no person in view: the test would prove nothing";
  const double ate_removed = computeAte(truth, with_removal).translation.rmse;
  const double ate_kept = computeAte(truth, without_removal).translation.rmse;
  EXPECT_LT(ate_removed, 0.005);
  EXPECT_GT(ate_kept, 2.0 * ate_removed);
  std::printf("synthetic xyz, 3 people, 30 frames: ATE %.4f m removed, %.4f m kept\n", ate_removed,
              ate_kept);
}

}  // namespace
}  // namespace pf2
