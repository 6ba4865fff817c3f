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

// The depths (metres, min < max) of the body a masked person's keypoints lie on; empty (0, 0)
// where there is no such band.
struct BodyDepthBand {
  double min = 0.0, max = 0.0;
  double mean = 0.0;  // of the person's depths inside (min, max)
  bool empty() const { return !(max > min); }
};

// The band of one person: the median depth under their confident keypoints
// (filter.joint_min_score, at least filter.joint_min_count) ± human_joint_band, when at least
// human_joint_min_share of `own_pixels` (their depths in the interval) lie in it. Empty without a
// mask, keypoints or enough depths near them, or with human_joint_band 0. Thread safe.
BodyDepthBand keypointDepthBand(const DualBBoxFilter::Person& person, const PersonDetection& detection,
                                const SlamOptions& options, long own_pixels);

// The largest group of the depths of `depth` (CV_32F, metres) inside `range`, when they fall into
// groups parted by at least `gap` metres in which (next to) none lie (under 1 % of them, binned at
// 5 cm) and the other groups hold at least min_share of them; else empty (and with gap 0). Thread
// safe.
BodyDepthBand largestDepthGroup(const cv::Mat& depth, const DepthInterval& range, double gap, double min_share);

// The depths d_m averages before any keypointDepthBand: the person's interval widened by
// filter.human_margin (with human_depth_in_interval and a mask), else all (0, infinity); valid.
// Thread safe.
DepthInterval intervalDepths(const DualBBoxFilter::Person& person, const PersonDetection* detection,
                             const SlamOptions& options);

// The box (image pixels, x_lr and y_lr one past the last) of person.depth's depths inside `range`
// (min < z < max), each side moved in past `trim` (0 <= trim < 0.5) of those depths; false, `box`
// untouched, when there are none. Thread safe.
bool ownDepthBox(const DualBBoxFilter::Person& person, const DepthInterval& range, double trim, PersonBox* box);

// d_m (metres) of one person (detection: theirs, or null): the mean of their depths inside their
// interval widened by filter.human_margin (with human_depth_in_interval and a mask), or inside
// their keypointDepthBand where it is not empty, else inside the largestDepthGroup of their
// interval's depths (human_group_gap) where there is one; 0 when they have no depth. *pixels gets the number
// of the person's depths in their interval; *band (optional) their band. Thread safe.
double personCentreDepth(const DualBBoxFilter::Person& person, const PersonDetection* detection,
                         const SlamOptions& options, long* pixels, BodyDepthBand* band = nullptr);

// The share of the person's keypoints scored at least min_score that lie on their depth D_h^t
// (within 2 px: the mask's edge); 1 when none scores that. A low share: the pose is someone else's
// (a merged mask whose one pose is the person behind the near one). Thread safe.
double keypointShareOnPerson(const DualBBoxFilter::Person& person, const PersonDetection& detection,
                             double min_score);

// What the body fit sees of the person: person.depth with only the depths inside `band`, or
// person.depth itself (shared) when the band is empty. Thread safe.
cv::Mat bodyDepth(const DualBBoxFilter::Person& person, const BodyDepthBand& band);

// What a person posed without a mask has of their own depth: person.depth on their skeleton
// (poseSkeleton, limbs kSkeletonLimbWidthShare of their box's height wide, keypoints scored
// filter.joint_min_score) within human_joint_band of the median depth under those keypoints;
// empty when fewer than filter.joint_min_count of them have depth. Their box holds the chair and
// the wall beside them at their depth as well. Thread safe.
cv::Mat posedBodyDepth(const DualBBoxFilter::Person& person, const PersonDetection& detection,
                       const SlamOptions& options);

// The depth under the masks of `people` (the filter's) that lies well behind their bodies: for
// each person with a mask and a keypointDepthBand, their depths more than `margin` behind both
// the band and the depth under their nearest confident keypoint (filter.joint_min_score) plus
// human_joint_band, and within kBehindBodyReach pixels (along each image axis) of their depths
// inside the band. The selfie mask's spill onto the wall, the desk or the chair behind a person;
// a body seen from above reaches far behind its band (the feet), not behind its own nearest
// keypoint. CV_8U of `size`, 255 there. Thread safe.
// The reach spares most of a second person the mask took in, further in (pf2_synth xyz seed 3:
// 0.21 points of the people's depth given back without it, 0.05 with it).
constexpr int kBehindBodyReach = 20;
cv::Mat depthBehindBodies(const std::vector<DualBBoxFilter::Person>& people, const Detections& detections,
                          const SlamOptions& options, double margin, const cv::Size& size);

// The people as the humans stage sees them: each of `people` whose detection (in `detections`)
// has at least filter.joint_min_count keypoints scored filter.joint_min_score or more, more than
// human_max_outside_pose of whose depths lie outside the region their body may fill (the box of
// those keypoints grown by a quarter of its size to the sides and up, and down to the image's
// bottom unless an ankle is among them), and the median of those outside more than
// human_joint_band behind the median of those inside, with its depth and mask cleared outside that
// region; the others as they are (sharing their images). Thread safe.
std::vector<DualBBoxFilter::Person> ownParts(const std::vector<DualBBoxFilter::Person>& people,
                                             const Detections& detections, const SlamOptions& options);

// One person the filter separated, placed by eq. 2.
struct PersonCentre {
  size_t person = 0;      // index into the filter's people
  Eigen::Vector3d p_c;    // camera frame, metres
  BodyDepthBand band;     // of personCentreDepth, for the body fit
  long pixels = 0;        // depths d_m rests on
};

// Eq. 2 for each of filtered.people with at least human_min_area of the image's pixels in depth,
// less those within human_same_body of a centre resting on more depths. Thread safe.
std::vector<PersonCentre> personCentres(const DualBBoxFilter::Result& filtered, const Detections& detections,
                                        const CameraIntrinsics& K, const SlamOptions& options);

}  // namespace pf2
