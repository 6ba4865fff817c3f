#pragma once
// Absolute trajectory error and relative pose error as the TUM RGB-D benchmark defines them
// (Sturm et al., IROS 2012, section VI).
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "pf2/core/pose.h"
#include "pf2/eval/error_statistics.h"

namespace pf2 {

struct AteOptions {
  // Estimate and ground truth stamps closer than this are associated (TUM: 0.02 s).
  double max_time_difference = 0.02;
  // Also estimate a scale (Umeyama's similarity); off = rigid alignment, as the TUM tool does.
  bool estimate_scale = false;
};

struct AteResult {
  ErrorStatistics translation;  // metres, per associated pose
  // p_gt ≈ scale * R * p_est + t: the alignment applied to the estimate.
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d translation_offset = Eigen::Vector3d::Zero();
  double scale = 1.0;
  // Associated (ground truth index, estimate index) pairs, sorted by ground truth time.
  std::vector<std::pair<size_t, size_t>> matches;
  std::vector<double> errors;                   // per match, metres
  std::vector<Eigen::Vector3d> aligned_estimate;  // per match, world frame of the ground truth
  std::vector<Eigen::Vector3d> ground_truth;      // per match
};

// Throws pf2::Error when fewer than three poses can be associated.
AteResult computeAte(const Trajectory& ground_truth, const Trajectory& estimate,
                     const AteOptions& options = AteOptions());

struct RpeOptions {
  enum class DeltaUnit { kSeconds, kFrames };
  // Time (or frame) distance between the two poses of a pair.
  double delta = 1.0;
  DeltaUnit unit = DeltaUnit::kSeconds;
  // Ground truth within this many seconds of an estimate stamp is used for it.
  double max_time_difference = 0.02;
};

struct RpeResult {
  ErrorStatistics translation;  // metres per delta
  ErrorStatistics rotation;     // degrees per delta
};

// For every estimate pose i, the pose j closest to i + delta (in time or in frames); the error is
// (E_i^-1 E_j)^-1 (G_i^-1 G_j) with G the ground truth nearest in time. All pairs, no sampling.
// Throws pf2::Error when no pair can be formed.
RpeResult computeRpe(const Trajectory& ground_truth, const Trajectory& estimate,
                     const RpeOptions& options = RpeOptions());

}  // namespace pf2
