#pragma once
// Poses for the frames tracking could not measure, filled in after a run. A person covering the
// view (or a sensor too close to see) leaves frames without static depth: online they get the
// motion prior's pose (bridged, the motion faded out) or none (lost). Once the camera is measured
// again after the gap (tracked or relocalised against a keyframe), where it went in between is
// bounded on both sides: each unmeasured frame between two measured ones gets a cubic Hermite
// position (the velocities measured just before and just after the gap at its ends) and a rotation
// slerped between the two ends. A gap longer than max_gap, or one without a measured frame after
// it (the run ended), keeps what tracking gave it.
//
// On pf2_synth with 5 people, halfsphere camera, seed 8 (a close person fills the view, nearer
// than the sensor's range): 16 bridged frames drifted 12 cm along the faded prior and 8 were lost;
// filled, the ATE went 15.6 -> 2.5 mm and 292 -> 300 of 300 frames have a pose
// (docs/BENCHMARKS.md, "More pf2_synth sequences"). Thread safe (const).
#include <vector>

#include <Eigen/Geometry>

namespace pf2 {

// One frame of a finished run, in time order.
struct RunFrame {
  double timestamp = 0;
  bool measured = false;  // the pose was measured (tracked or relocalised); false: bridged or lost
  bool has_pose = false;  // a pose at all (measured frames always have one)
  bool restarts = false;  // relocalised: the motion from the frame before is unknown, so no end
                          // velocity is measured across it
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
};

class GapInterpolator {
 public:
  struct Options {
    double max_gap = 3.0;          // s between the measured frames around a gap; longer gaps are left
                                   // as tracking gave them (0 = never fill), [0, 60]
    double velocity_window = 0.2;  // s of measured frames before / after a gap its end velocities are
                                   // taken over; shorter runs of them make the ends' velocity the
                                   // gap's mean one, [0.01, 5]
  };

  explicit GapInterpolator(const Options& options) : options_(options) {}

  // Fills every gap it may (see above) in place: has_pose becomes true and T_w_c the filled pose.
  // Returns the indices of the frames filled, in order.
  std::vector<size_t> fill(std::vector<RunFrame>* frames) const;

 private:
  // The velocity over the measured frames from `end` stepping by `step` (-1: before, +1: after)
  // within velocity_window and not across a restart; false when there are not two such frames.
  bool endVelocity(const std::vector<RunFrame>& frames, size_t end, int step, Eigen::Vector3d* velocity) const;
  void fillGap(size_t before, size_t after, std::vector<RunFrame>* frames) const;

  Options options_;
};

}  // namespace pf2
