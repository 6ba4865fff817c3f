#include "pf2/eval/body_metrics.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "pf2/core/error.h"
#include "pf2/core/text_lines.h"

namespace pf2 {

long long timestampMicros(double timestamp) { return std::llround(timestamp * 1e6); }

std::map<PersonFrameKey, BodyJoints> readGroundTruthJoints(const std::string& path) {
  std::map<PersonFrameKey, BodyJoints> joints;
  forEachDataLine(path, "joints file", [&](const std::string& line, int number) {
    std::istringstream fields(line);
    double stamp = 0;
    int id = 0;
    BodyJoints j;
    bool ok = static_cast<bool>(fields >> stamp >> id);
    for (auto& p : j) ok = ok && static_cast<bool>(fields >> p.x() >> p.y() >> p.z()) && p.allFinite();
    if (!ok || !std::isfinite(stamp)) {
      throw fileError(path, number, "expected 'timestamp id' and 72 finite joint coordinates");
    }
    joints[{timestampMicros(stamp), id}] = j;
  });
  return joints;
}

BodyMetrics evaluateBodies(const std::vector<BodyTrack>& bodies, const Eigen::Isometry3d& T_gt_est,
                           const std::map<PersonFrameKey, BodyJoints>& truth, double match_distance) {
  BodyMetrics metrics;
  std::vector<double> all, fitted;
  std::array<std::vector<double>, kBodyJointCount> per_joint;
  for (const BodyTrack& track : bodies) {
    for (const BodyTrackFrame& frame : track.frames) {
      const long long stamp = timestampMicros(frame.timestamp);
      const Eigen::Vector3d pelvis = T_gt_est * frame.pelvis_w;
      const BodyJoints* best = nullptr;
      double best_distance = match_distance;
      for (auto it = truth.lower_bound({stamp, -1}); it != truth.end() && it->first.first == stamp; ++it) {
        const double d = (it->second[0] - pelvis).norm();
        if (d <= best_distance) best_distance = d, best = &it->second;
      }
      if (best == nullptr) {
        ++metrics.unmatched;
        continue;
      }
      double sum = 0;
      for (int j = 0; j < kBodyJointCount; ++j) {
        const double e = (T_gt_est * frame.joints_w[j] - (*best)[j]).norm();
        per_joint[j].push_back(e);
        sum += e;
      }
      all.push_back(sum / kBodyJointCount);
      if (frame.fitted) fitted.push_back(sum / kBodyJointCount);
      ++metrics.body_frames;
    }
  }
  metrics.mpjpe = computeErrorStatistics(all);
  metrics.mpjpe_fitted = computeErrorStatistics(fitted);
  for (int j = 0; j < kBodyJointCount; ++j) metrics.joint_median[j] = computeErrorStatistics(per_joint[j]).median;
  return metrics;
}

}  // namespace pf2
