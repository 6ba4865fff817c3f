#include "pf2/filters/person_removal.h"

#include "pf2/core/error.h"

namespace pf2 {

PersonRemoval::PersonRemoval(const Options& options, std::unique_ptr<HumanDetector> detector)
    : options_(options),
      detector_(std::move(detector)),
      filter_(options.filter),
      evidence_(std::make_shared<PredictedDepthEvidence>(options.geometric_margin, options.geometric_opening)) {
  if (!detector_) throw Error("PersonRemoval: a detector is required");
  evidence_->setStaticMargin(options.static_margin);
  evidence_->setPlaneMargin(options.floor_margin);
  filter_.setDynamicEvidence(evidence_);
}

Detections PersonRemoval::detect(const Frame& frame, StageStats* stats) {
  Detections detections;
  {
    ScopedStageTimer timer(stats, "detect");
    detections = detector_->detect(frame);
  }
  degradeDetections(options_.degradation, frame.depth.size(), &detections);
  return detections;
}

DualBBoxFilter::Result PersonRemoval::filter(const Frame& frame, const Detections& detections,
                                             const Eigen::Isometry3d& T_cur_prev, const cv::Mat& prediction,
                                             StageStats* stats,
                                             const std::optional<Eigen::Hyperplane<double, 3>>& floor_c) {
  ScopedStageTimer timer(stats, "filter");
  filter_.setIntrinsics(frame.intrinsics);
  // Without the geometric addition the prediction's static opinion goes too; the floor stays.
  evidence_->setPrediction(options_.filter.geometric ? prediction : cv::Mat());
  evidence_->setStaticPlane(floor_c, frame.intrinsics);
  return filter_.filter(frame.depth, detections, T_cur_prev);
}

}  // namespace pf2
