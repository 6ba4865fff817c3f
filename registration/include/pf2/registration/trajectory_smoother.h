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
#include <utility>
#include <vector>

#include "pf2/core/pose.h"

namespace pf2 {

class TrajectorySmoother {
 public:
  struct Options {
    double position_noise = 0.005;   // metres: scatter of one frame's measured position; 0 = off
    // m/s^2, > 0: typical acceleration of the camera, per axis, where the run does not measure its
    // own (measure_acceleration false, or a run shorter than three acceleration_baselines). A
    // looser value lets the smoother follow the odometry's wobble over a few frames, a stiller one
    // cuts real motion (docs/BENCHMARKS.md, "Tracking with the learned detector").
    double acceleration_noise = 0.5;
    // true: the acceleration noise is measured from the run itself, as acceleration_scale times
    // the RMS acceleration of its measured positions along their busiest axis, taken as second
    // differences of the positions resampled every acceleration_baseline seconds, and at least
    // acceleration_floor. Over half a second the odometry's scatter adds only about
    // sqrt(6) * position_noise / baseline^2 = 0.05 m/s^2, so a still camera, a slow hand-held one
    // and a fast one can be told apart (estimated / true RMS: Bonn crowd 0.13 / 0.10, TUM fr1/rpy
    // 0.17 / 0.14, pf2_synth xyz 0.36 / 0.35, static 0.01 / 0), which one fixed value cannot do.
    bool measure_acceleration = true;
    double acceleration_baseline = 0.5;  // seconds, > 0
    // > 0: the camera's accelerations within a frame or two are larger than their half-second
    // average (ground truth: 1.1x on pf2_synth paths, 1.5-1.9x on the hand-held Bonn and TUM ones)
    double acceleration_scale = 1.5;
    double acceleration_floor = 0.1;     // m/s^2, > 0: the least measured acceleration noise
    double max_gap = 0.5;            // seconds between frames that ends a segment
  };

  // Throws pf2::Error when measure_acceleration is on and acceleration_baseline,
  // acceleration_scale or acceleration_floor is not > 0.
  explicit TrajectorySmoother(const Options& options);

  // The trajectory (sorted by time) with smoothed positions. restarts: empty, or one flag per
  // pose, true where the pose does not follow from the one before (a new segment starts there).
  Trajectory smooth(const Trajectory& measured, const std::vector<bool>& restarts = {}) const;

  // The acceleration noise smooth() uses on `measured` (sorted by time, same restarts): the
  // measured one (Options::measure_acceleration) or Options::acceleration_noise.
  double accelerationNoise(const Trajectory& measured, const std::vector<bool>& restarts = {}) const;

 private:
  // [begin, end) index ranges of the pieces smoothed apart (gaps and restarts end a piece).
  std::vector<std::pair<size_t, size_t>> segments(const Trajectory& measured, const std::vector<bool>& restarts) const;
  void smoothSegment(const Trajectory& measured, size_t begin, size_t end, double acceleration_noise,
                     Trajectory* out) const;

  Options options_;
};

}  // namespace pf2
