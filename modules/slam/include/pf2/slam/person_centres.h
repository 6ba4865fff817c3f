#pragma once
// Where each person the filter separated stands in the camera frame: eq. 2 (pf2/humans/
// human_position.h) with d_m taken over the depths that are the person's own.
#include <vector>

#include <Eigen/Core>

#include "pf2/core/camera_intrinsics.h"
#include "pf2/detection/human_detector.h"
#include "pf2/filters/dual_bbox_filter.h"
#include "pf2/slam/slam_options.h"

namespace pf2 {

// d_m (metres) of one person (detection: theirs, or null), from options.human_depth_in_interval,
// filter.human_margin, human_joint_band and human_joint_min_share (slam_options.h); 0 when they
// have no depth. *pixels gets the number of the person's depths in their interval. Thread safe.
double personCentreDepth(const DualBBoxFilter::Person& person, const PersonDetection* detection,
                         const SlamOptions& options, long* pixels);

// Eq. 2 for each of filtered.people with at least human_min_area of the image's pixels in depth;
// *person_of_centre gets the index into filtered.people of each centre. Thread safe.
std::vector<Eigen::Vector3d> personCentres(const DualBBoxFilter::Result& filtered, const Detections& detections,
                                           const CameraIntrinsics& K, const SlamOptions& options,
                                           std::vector<size_t>* person_of_centre);

}  // namespace pf2
