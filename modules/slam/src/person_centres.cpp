#include "pf2/slam/person_centres.h"

#include <algorithm>
#include <limits>

#include "pf2/detection/keypoint_depth.h"
#include "pf2/humans/human_position.h"

namespace pf2 {

// With human_depth_in_interval, a person whose detection came with a mask averages only the depths
// inside their interval widened by the filter's human_margin: the dilated mask is taken whatever
// its depth, so it brings in the edges of whoever stands in front or behind (without a mask the
// filter has already kept only depths of the person's intervals). With human_joint_band, of those
// only the ones near the depth under the person's keypoints, when enough lie there: a mask that
// merged two people, one in front of the other, holds both in one interval and its mean lies
// between them.
double personCentreDepth(const DualBBoxFilter::Person& person, const PersonDetection* detection,
                         const SlamOptions& options, long* pixels) {
  const bool masked = detection && !detection->mask.empty();
  const bool use_interval = options.human_depth_in_interval && masked && person.interval.valid;
  const double margin = options.filter.human_margin;
  const double d_m = meanDepth(person.depth, use_interval ? person.interval.min - margin : 0.0,
                               use_interval ? person.interval.max + margin : std::numeric_limits<double>::infinity(),
                               pixels);
  if (!masked || !(options.human_joint_band > 0.0) || *pixels == 0) return d_m;
  const double joints =
      medianDepthAtKeypoints(person.depth, person.area.tl(), detection->keypoints, options.filter.joint_min_score,
                             std::max(1, options.filter.joint_min_count), std::numeric_limits<double>::infinity());
  if (joints <= 0.0) return d_m;
  long near_pixels = 0;
  const double d_near =
      meanDepth(person.depth, joints - options.human_joint_band, joints + options.human_joint_band, &near_pixels);
  return near_pixels > 0 && near_pixels >= options.human_joint_min_share * *pixels ? d_near : d_m;
}

// Box centre at d_m (eq. 2). People whose depths cover less than human_min_area of the image get no
// centre: a sliver of a person gives a box centre far from the body.
std::vector<Eigen::Vector3d> personCentres(const DualBBoxFilter::Result& filtered, const Detections& detections,
                                           const CameraIntrinsics& K, const SlamOptions& options,
                                           std::vector<size_t>* person_of_centre) {
  const double min_pixels = options.human_min_area * filtered.static_depth.total();
  std::vector<Eigen::Vector3d> centres_c;
  for (size_t index = 0; index < filtered.people.size(); ++index) {
    const DualBBoxFilter::Person& person = filtered.people[index];
    const bool detected = person.detection >= 0 && person.detection < static_cast<int>(detections.people.size());
    long pixels = 0;
    const PersonDetection* detection = detected ? &detections.people[person.detection] : nullptr;
    const double d_m = personCentreDepth(person, detection, options, &pixels);
    if (pixels == 0 || pixels < min_pixels) continue;
    centres_c.push_back(humanCentreInCamera(person.box.x_ul, person.box.y_ul, person.box.x_lr,
                                            person.box.y_lr, d_m, K));
    person_of_centre->push_back(index);
  }
  return centres_c;
}

}  // namespace pf2
