#pragma once
// Which of a person's depths are their own, for where they stand (eq. 2, pf2/humans/
// human_position.h) and for their body fit. The filter's D_h^t of a person holds every depth under
// their dilated mask in their interval; when the segmentation merged two people, one in front of
// the other, both are in it, and the keypoints tell whose body the detection is.
#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"
#include "pf2/detection/human_detector.h"
#include "pf2/filters/dual_bbox_filter.h"
#include "pf2/slam/slam_options.h"

namespace pf2 {

// The depth band of the body a masked person's keypoints lie on: the median depth under their
// confident keypoints (filter.joint_min_score, at least filter.joint_min_count) ± human_joint_band,
// when at least human_joint_min_share of `own_pixels` (their depths in the interval) lie in it.
// False (no band) without a mask, keypoints or enough depths near them, or with human_joint_band 0.
// Thread safe.
bool keypointDepthBand(const DualBBoxFilter::Person& person, const PersonDetection& detection,
                       const SlamOptions& options, long own_pixels, double* min_depth, double* max_depth);

// d_m (metres) of one person (detection: theirs, or null): the mean of their depths inside their
// interval widened by filter.human_margin (with human_depth_in_interval and a mask), or inside
// keypointDepthBand where there is one; 0 when they have no depth. *pixels gets the number of the
// person's depths in their interval. Thread safe.
double personCentreDepth(const DualBBoxFilter::Person& person, const PersonDetection* detection,
                         const SlamOptions& options, long* pixels);

// What the body fit sees of the person: person.depth with only the depths inside
// keypointDepthBand, or person.depth itself (shared) where there is no band. Thread safe.
cv::Mat bodyDepth(const DualBBoxFilter::Person& person, const PersonDetection& detection, const SlamOptions& options);

// Eq. 2 for each of filtered.people with at least human_min_area of the image's pixels in depth;
// *person_of_centre gets the index into filtered.people of each centre. Thread safe.
std::vector<Eigen::Vector3d> personCentres(const DualBBoxFilter::Result& filtered, const Detections& detections,
                                           const CameraIntrinsics& K, const SlamOptions& options,
                                           std::vector<size_t>* person_of_centre);

}  // namespace pf2
