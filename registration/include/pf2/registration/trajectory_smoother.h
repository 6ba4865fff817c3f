#pragma once
// Fixed-interval smoothing of a finished run's camera positions (T_w_c translations). Each frame's
// pose is measured on its own against its keyframe, so consecutive positions scatter by a few
// millimetres along the directions a rotation can mimic (on the Bonn crowd frames, 6 mm between
// consecutive frames while the camera moved 2 mm), while a hand-held or robot camera accelerates
// smoothly. The smoother weighs both: it minimises
//   sum_i |x_i - m_i|^2 / position_noise^2  +  sum_i |v_i+ - v_i-|^2 / (acceleration_noise * dt_i)^2
// over the positions x of each segment, m being the measured positions, v_i- and v_i+ the
// velocities into and out of frame i and dt_i the mean of their time steps. Orientations are left
// as measured. A segment ends where frames are more than max_gap apart or where a pose restarts
// (a relocalised frame: the motion across the gap is unknown). Thread safe (const).
#include <vector>

#include "pf2/core/pose.h"

namespace pf2 {

class TrajectorySmoother {
 public:
  struct Options {
    double position_noise = 0.005;   // metres: scatter of one frame's measured position; 0 = off
    // m/s^2: typical acceleration of the camera, per axis. The ground truth of the hand-held
    // cameras we have moves at 0.14 (Bonn crowd), 0.32 (TUM fr1/rpy) and 0.39 (pf2_synth xyz, the
    // fastest of its paths) m/s^2 RMS along its busiest axis, measured over 0.2 s; 0.5 covers them
    // all. A looser value lets the smoother follow the odometry's wobble over a few frames, a
    // stiller one cuts real motion (docs/BENCHMARKS.md, "Tracking with the learned detector").
    double acceleration_noise = 0.5;
    double max_gap = 0.5;            // seconds between frames that ends a segment
  };

  explicit TrajectorySmoother(const Options& options) : options_(options) {}

  // The trajectory (sorted by time) with smoothed positions. restarts: empty, or one flag per
  // pose, true where the pose does not follow from the one before (a new segment starts there).
  Trajectory smooth(const Trajectory& measured, const std::vector<bool>& restarts = {}) const;

 private:
  void smoothSegment(const Trajectory& measured, size_t begin, size_t end, Trajectory* out) const;

  Options options_;
};

}  // namespace pf2
