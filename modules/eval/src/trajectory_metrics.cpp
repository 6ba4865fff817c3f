#include "pf2/eval/trajectory_metrics.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>

#include "pf2/core/error.h"
#include "pf2/io/tum_lists.h"

namespace pf2 {

namespace {

std::vector<double> stampsOf(const Trajectory& trajectory) {
  std::vector<double> stamps;
  stamps.reserve(trajectory.size());
  for (const StampedPose& pose : trajectory) stamps.push_back(pose.timestamp);
  return stamps;
}

// Index of the stamp closest to t in a sorted list (which must not be empty).
size_t closestIndex(const std::vector<double>& sorted_stamps, double t) {
  const auto after = std::lower_bound(sorted_stamps.begin(), sorted_stamps.end(), t);
  if (after == sorted_stamps.begin()) return 0;
  if (after == sorted_stamps.end()) return sorted_stamps.size() - 1;
  const size_t j = after - sorted_stamps.begin();
  return (t - sorted_stamps[j - 1] <= sorted_stamps[j] - t) ? j - 1 : j;
}

}  // namespace

AteResult computeAte(const Trajectory& ground_truth, const Trajectory& estimate,
                     const AteOptions& options) {
  AteResult result;
  result.matches =
      associateTimestamps(stampsOf(ground_truth), stampsOf(estimate), options.max_time_difference);
  const size_t n = result.matches.size();
  if (n < 3) {
    throw Error("only " + std::to_string(n) + " estimate poses lie within " +
                std::to_string(options.max_time_difference) +
                " s of a ground truth pose; need at least 3 (wrong file or time base?)");
  }
  Eigen::Matrix3Xd gt(3, n), est(3, n);
  for (size_t k = 0; k < n; ++k) {
    gt.col(k) = ground_truth[result.matches[k].first].T_w_c.translation();
    est.col(k) = estimate[result.matches[k].second].T_w_c.translation();
  }
  // Closed-form least-squares alignment (Horn 1987 / Umeyama 1991) of estimate onto ground truth.
  const Eigen::Matrix4d similarity = Eigen::umeyama(est, gt, options.estimate_scale);
  result.scale = options.estimate_scale ? similarity.block<3, 1>(0, 0).norm() : 1.0;
  result.rotation = similarity.block<3, 3>(0, 0) / result.scale;
  result.translation_offset = similarity.block<3, 1>(0, 3);
  result.errors.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d aligned =
        result.scale * result.rotation * est.col(k) + result.translation_offset;
    result.aligned_estimate.push_back(aligned);
    result.ground_truth.push_back(gt.col(k));
    result.errors[k] = (aligned - gt.col(k)).norm();
  }
  result.translation = computeErrorStatistics(result.errors);
  return result;
}

RpeResult computeRpe(const Trajectory& ground_truth, const Trajectory& estimate,
                     const RpeOptions& options) {
  if (ground_truth.empty() || estimate.empty()) throw Error("RPE needs two non-empty trajectories");
  if (!(options.delta > 0.0)) throw Error("RPE delta must be positive");
  const std::vector<double> gt_stamps = stampsOf(ground_truth);
  const std::vector<double> est_stamps = stampsOf(estimate);
  std::vector<double> translation_errors, rotation_errors;
  for (size_t i = 0; i < estimate.size(); ++i) {
    size_t j;
    if (options.unit == RpeOptions::DeltaUnit::kFrames) {
      j = i + static_cast<size_t>(std::lround(options.delta));
      if (j >= estimate.size()) break;
    } else {
      const double target = est_stamps[i] + options.delta;
      if (target > est_stamps.back() + options.max_time_difference) break;
      j = closestIndex(est_stamps, target);
      if (j <= i) continue;
    }
    const size_t gi = closestIndex(gt_stamps, est_stamps[i]);
    const size_t gj = closestIndex(gt_stamps, est_stamps[j]);
    if (std::abs(gt_stamps[gi] - est_stamps[i]) > options.max_time_difference ||
        std::abs(gt_stamps[gj] - est_stamps[j]) > options.max_time_difference) {
      continue;
    }
    const Eigen::Isometry3d estimate_motion = estimate[i].T_w_c.inverse() * estimate[j].T_w_c;
    const Eigen::Isometry3d true_motion = ground_truth[gi].T_w_c.inverse() * ground_truth[gj].T_w_c;
    const Eigen::Isometry3d error = estimate_motion.inverse() * true_motion;
    translation_errors.push_back(error.translation().norm());
    rotation_errors.push_back(rotationAngle(error.rotation()) * 180.0 / M_PI);
  }
  if (translation_errors.empty()) {
    throw Error("RPE: no pose pair at the requested delta has ground truth within " +
                std::to_string(options.max_time_difference) + " s");
  }
  RpeResult result;
  result.translation = computeErrorStatistics(translation_errors);
  result.rotation = computeErrorStatistics(rotation_errors);
  return result;
}

}  // namespace pf2
