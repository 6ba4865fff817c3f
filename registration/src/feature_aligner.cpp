#include "pf2/registration/feature_aligner.h"

#include <algorithm>
#include <cmath>
#include <random>

#include <Eigen/Geometry>
#include <opencv2/features2d.hpp>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

Eigen::Isometry3d rigidFit(const std::vector<Eigen::Vector3d>& from,
                           const std::vector<Eigen::Vector3d>& to, const std::vector<int>& ids) {
  Eigen::Matrix3Xd src(3, ids.size()), dst(3, ids.size());
  for (size_t i = 0; i < ids.size(); ++i) {
    src.col(i) = from[ids[i]];
    dst.col(i) = to[ids[i]];
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.matrix() = Eigen::umeyama(src, dst, false);
  return T;
}

}  // namespace

FeatureAligner::FeatureAligner() : FeatureAligner(Options()) {}
FeatureAligner::FeatureAligner(const Options& options) : options_(options) {}

void FeatureAligner::extract(OdometryFrame* frame) const {
  if (frame->has_features) return;
  if (frame->levels.empty() || frame->gray.empty()) throw Error("FeatureAligner: frame not prepared");
  // cv::ORB keeps state between calls, so each call gets its own detector (creation is cheap).
  cv::Ptr<cv::ORB> orb = cv::ORB::create(options_.max_features, 1.2f, options_.pyramid_levels, 19,
                                         0, 2, cv::ORB::HARRIS_SCORE, 31, options_.fast_threshold);
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
  orb->detectAndCompute(frame->gray, frame->feature_mask, keypoints, descriptors);
  const OdometryLevel& level0 = frame->levels[0];
  frame->keypoints.clear();
  frame->keypoint_points.clear();
  cv::Mat kept(0, descriptors.cols, CV_8U);
  for (size_t i = 0; i < keypoints.size(); ++i) {
    const int u = cvRound(keypoints[i].pt.x), v = cvRound(keypoints[i].pt.y);
    if (u < 0 || v < 0 || u >= level0.depth.cols || v >= level0.depth.rows) continue;
    const float z = level0.depth.at<float>(v, u);
    if (!(z > 0.0f)) continue;
    frame->keypoints.push_back(keypoints[i]);
    frame->keypoint_points.push_back(
        level0.intrinsics.backProject(keypoints[i].pt.x, keypoints[i].pt.y, z));
    kept.push_back(descriptors.row(static_cast<int>(i)));
  }
  frame->descriptors = kept;
  frame->has_features = true;
}

SparseAlignment FeatureAligner::align(const OdometryFrame& reference,
                                      const OdometryFrame& current) const {
  if (!reference.has_features || !current.has_features)
    throw Error("FeatureAligner::align: features not extracted");
  SparseAlignment result;
  if (reference.descriptors.rows < 3 || current.descriptors.rows < 3) return result;

  cv::BFMatcher matcher(cv::NORM_HAMMING);
  std::vector<std::vector<cv::DMatch>> knn;
  matcher.knnMatch(current.descriptors, reference.descriptors, knn, 2);
  std::vector<Eigen::Vector3d> p_cur, p_ref;
  for (const auto& m : knn) {
    if (m.empty() || m[0].distance > options_.max_hamming) continue;
    if (m.size() > 1 && m[0].distance >= options_.ratio * m[1].distance) continue;
    p_cur.push_back(current.keypoint_points[m[0].queryIdx]);
    p_ref.push_back(reference.keypoint_points[m[0].trainIdx]);
  }
  const int n = static_cast<int>(p_cur.size());
  result.matches = n;
  if (n < 3) return result;

  // Inlier threshold per match, from the reference depth (noise grows with z^2).
  std::vector<double> threshold2(n);
  for (int i = 0; i < n; ++i) {
    const double z = std::max(1.0, p_ref[i].z());
    const double t = options_.inlier_distance * z * z;
    threshold2[i] = t * t;
  }
  auto countInliers = [&](const Eigen::Isometry3d& T, std::vector<int>* ids) {
    ids->clear();
    for (int i = 0; i < n; ++i)
      if ((T * p_cur[i] - p_ref[i]).squaredNorm() < threshold2[i]) ids->push_back(i);
    return static_cast<int>(ids->size());
  };

  std::mt19937 rng(options_.random_seed);
  std::uniform_int_distribution<int> pick(0, n - 1);
  std::vector<int> best, ids, sample(3);
  for (int it = 0; it < options_.ransac_iterations; ++it) {
    sample[0] = pick(rng);
    do sample[1] = pick(rng); while (sample[1] == sample[0]);
    do sample[2] = pick(rng); while (sample[2] == sample[0] || sample[2] == sample[1]);
    // Degenerate (nearly collinear) samples give no rotation; skip them.
    const Eigen::Vector3d a = p_cur[sample[1]] - p_cur[sample[0]];
    const Eigen::Vector3d b = p_cur[sample[2]] - p_cur[sample[0]];
    if (a.cross(b).norm() < 1e-4) continue;
    const Eigen::Isometry3d T = rigidFit(p_cur, p_ref, sample);
    if (countInliers(T, &ids) > static_cast<int>(best.size())) best = ids;
    if (static_cast<int>(best.size()) > 0.9 * n) break;
  }
  if (best.size() < 3) return result;
  // Refit on the inliers, then once more on the inliers of the refit.
  Eigen::Isometry3d T = rigidFit(p_cur, p_ref, best);
  countInliers(T, &ids);
  if (ids.size() >= 3) {
    T = rigidFit(p_cur, p_ref, ids);
    countInliers(T, &ids);
  }
  double sum2 = 0.0;
  for (int i : ids) sum2 += (T * p_cur[i] - p_ref[i]).squaredNorm();
  result.T_ref_cur = T;
  result.inliers = static_cast<int>(ids.size());
  result.inlier_rmse = ids.empty() ? 0.0 : std::sqrt(sum2 / ids.size());
  result.valid = result.inliers >= options_.min_inliers &&
                 result.inliers >= options_.min_inlier_fraction * n;
  return result;
}

}  // namespace pf2
