#pragma once
// The person-removal front end pf2_slam and pf2_detect both run: a detector's people (degraded
// on request, for experiments), then the Dual-BBox filter with its additions, given the camera's
// motion since the last frame (temporal guard) and a static depth predicted for this view
// (geometric addition). Where the motion and the prediction come from is the caller's: pf2_slam
// has its tracker and keyframes, pf2_detect the ground truth and its stand-in model.
//
// One frame at a time, in order. NOT thread safe (the detector and the filter keep state).
#include <memory>
#include <optional>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/frame.h"
#include "pf2/core/stage_timer.h"
#include "pf2/detection/box_degradation.h"
#include "pf2/detection/human_detector.h"
#include "pf2/filters/dual_bbox_filter.h"

namespace pf2 {

class PersonRemoval {
 public:
  struct Options {
    DualBBoxFilter::Options filter;
    BoxDegradation degradation;      // applied to every frame's detections; none by default
    double geometric_margin = 0.15;  // metres: depth this far in front of the prediction is dynamic
    int geometric_opening = 0;       // pixels: the dynamic mask is opened by a disc this wide
    double static_margin = 0.0;      // metres (plus 1 % of the depth): this close to the prediction
                                     // is known static (filter.keep_static); 0 = no static evidence
    double floor_margin = 0.0;       // metres (plus 1 % of the depth): this close to the floor plane
                                     // is known static (filter.keep_static); 0 = no floor evidence
  };

  // Throws pf2::Error when detector is null.
  PersonRemoval(const Options& options, std::unique_ptr<HumanDetector> detector);

  // The frame's people, degraded per Options (stage "detect" in stats).
  Detections detect(const Frame& frame, StageStats* stats);
  // The Dual-BBox filter on the frame's depth (stage "filter"): T_cur_prev moves the previous
  // frame's points into this one (identity without a guess); prediction is the static depth
  // predicted for this view (CV_32F metres, 0 = unknown), empty for no geometric opinion, and used
  // only with filter.geometric; floor_c is the floor plane in this view's camera frame, if known,
  // used with or without it (a scene prior, not a residual: static where keep_static is on).
  DualBBoxFilter::Result filter(const Frame& frame, const Detections& detections, const Eigen::Isometry3d& T_cur_prev,
                                const cv::Mat& prediction, StageStats* stats,
                                const std::optional<Eigen::Hyperplane<double, 3>>& floor_c = std::nullopt);

  const HumanDetector& detector() const { return *detector_; }
  const Options& options() const { return options_; }

 private:
  Options options_;
  std::unique_ptr<HumanDetector> detector_;
  DualBBoxFilter filter_;
  std::shared_ptr<PredictedDepthEvidence> evidence_;
};

}  // namespace pf2
