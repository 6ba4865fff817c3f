#include "pf2/slam/person_centres.h"

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "pf2/detection/keypoint_depth.h"
#include "pf2/detection/pose_skeleton.h"
#include "pf2/humans/human_position.h"
#include "pf2/core/median.h"

namespace pf2 {

namespace {

// The median of person.depth under the detection's confident keypoints (filter.joint_min_score, at
// least filter.joint_min_count of them); 0 when fewer have depth.
double keypointsMedianDepth(const DualBBoxFilter::Person& person, const PersonDetection& detection,
                            const SlamOptions& options) {
  return medianDepthAtKeypoints(person.depth, person.area.tl(), detection.keypoints, options.filter.joint_min_score,
                                std::max(1, options.filter.joint_min_count), std::numeric_limits<double>::infinity());
}

}  // namespace

BodyDepthBand keypointDepthBand(const DualBBoxFilter::Person& person, const PersonDetection& detection,
                                const SlamOptions& options, long own_pixels) {
  if (detection.mask.empty() || !(options.human_joint_band > 0.0) || own_pixels == 0) return {};
  const double joints = keypointsMedianDepth(person, detection, options);
  if (joints <= 0.0) return {};
  BodyDepthBand band{joints - options.human_joint_band, joints + options.human_joint_band};
  long near_pixels = 0;
  band.mean = meanDepth(person.depth, band.min, band.max, &near_pixels);
  // Fewer: the keypoints lie on a sliver (those of a near person cut by the border may land on
  // the wall at the mask's edge).
  if (near_pixels == 0 || near_pixels < options.human_joint_min_share * own_pixels) return {};
  return band;
}

namespace {

// Calls visit(z) for each depth z of `depth` (CV_32F, metres) with range.min < z < range.max.
template <typename Visit>
void forEachDepthIn(const cv::Mat& depth, const DepthInterval& range, Visit visit) {
  for (int v = 0; v < depth.rows; ++v) {
    const float* row = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; ++u) {
      if (row[u] > range.min && row[u] < range.max) visit(row[u]);
    }
  }
}

// The groups ([first, last] bin index) of a depth histogram `bins` (summing to `total`) that runs
// of at least `gap_bins` bins, together holding less than stray_share of the total, part.
std::vector<std::pair<size_t, size_t>> binGroups(const std::vector<long>& bins, long total, double gap_bins,
                                                 double stray_share) {
  const double stray = stray_share * static_cast<double>(total);
  std::vector<std::pair<size_t, size_t>> groups;
  size_t start = 0;  // first bin of the group being grown
  for (size_t b = 0; b < bins.size();) {
    // The longest run of bins from b holding less than `stray` depths.
    size_t end = b;
    long held = 0;
    while (end < bins.size() && static_cast<double>(held + bins[end]) < stray) held += bins[end++];
    const bool parts = static_cast<double>(end - b) >= gap_bins && b > start && end < bins.size();
    if (parts) {
      groups.emplace_back(start, b - 1);
      start = end;
    }
    b = std::max(end, b + 1);
  }
  groups.emplace_back(start, bins.size() - 1);
  return groups;
}

}  // namespace

// With human_depth_in_interval, a person whose detection came with a mask averages only the depths
// inside their interval widened by the filter's human_margin: the dilated mask is taken whatever
// its depth, so it brings in the edges of whoever stands in front or behind (without a mask the
// filter has already kept only depths of the person's intervals).
double personCentreDepth(const DualBBoxFilter::Person& person, const PersonDetection* detection,
                         const SlamOptions& options, long* pixels, BodyDepthBand* band_out) {
  const DepthInterval range = intervalDepths(person, detection, options);
  const double d_m = meanDepth(person.depth, range.min, range.max, pixels);
  BodyDepthBand band = detection ? keypointDepthBand(person, *detection, options, *pixels) : BodyDepthBand();
  if (band.empty()) band = largestDepthGroup(person.depth, range, options.human_group_gap, options.human_group_min_share);
  if (band_out) *band_out = band;
  return band.empty() ? d_m : band.mean;
}

BodyDepthBand largestDepthGroup(const cv::Mat& depth, const DepthInterval& range, double gap, double min_share) {
  if (!(gap > 0.0)) return {};
  // Depths binned at kBin metres between the nearest and the farthest inside `range`.
  constexpr double kBin = 0.05;
  // A stretch of bins holding less than this share of the depths still parts two groups: the
  // sensor's mixed pixels along one person's outline over the other lie between the two.
  constexpr double kStrayShare = 0.01;
  double nearest = std::numeric_limits<double>::infinity(), farthest = 0.0;
  forEachDepthIn(depth, range, [&](float z) { nearest = std::min<double>(nearest, z), farthest = std::max<double>(farthest, z); });
  if (!(farthest > nearest + gap)) return {};
  std::vector<long> bins(static_cast<size_t>((farthest - nearest) / kBin) + 1, 0);
  long total = 0;
  forEachDepthIn(depth, range, [&](float z) { ++bins[static_cast<size_t>((z - nearest) / kBin)], ++total; });
  const std::vector<std::pair<size_t, size_t>> groups = binGroups(bins, total, gap / kBin, kStrayShare);
  if (groups.size() < 2) return {};
  std::pair<size_t, size_t> largest = groups.front();
  long largest_count = 0;
  for (const auto& [first, last] : groups) {
    long count = 0;
    for (size_t b = first; b <= last; ++b) count += bins[b];
    if (count > largest_count) largest = {first, last}, largest_count = count;
  }
  if (static_cast<double>(total - largest_count) < min_share * static_cast<double>(total)) return {};
  // The band's bounds are exclusive: its lower one half a bin below the group's first bin, so that
  // the nearest depth itself lies inside.
  BodyDepthBand band{nearest + kBin * (static_cast<double>(largest.first) - 0.5),
                     nearest + kBin * static_cast<double>(largest.second + 1)};
  band.mean = meanDepth(depth, band.min, band.max);
  return band;
}

DepthInterval intervalDepths(const DualBBoxFilter::Person& person, const PersonDetection* detection,
                             const SlamOptions& options) {
  const bool masked = detection && !detection->mask.empty();
  if (!(options.human_depth_in_interval && masked && person.interval.valid)) {
    return {0.0, std::numeric_limits<double>::infinity(), true};
  }
  const double margin = options.filter.human_margin;
  return {person.interval.min - margin, person.interval.max + margin, true};
}

namespace {

// The first and the last index of `counts` (summing to `total` > 0) past which more than `trim` of
// the total lies on the far side: [first, last] holds all but trim of it at each end.
std::pair<int, int> trimmedSpan(const std::vector<long>& counts, long total, double trim) {
  const double outside = trim * static_cast<double>(total);
  int first = 0, last = static_cast<int>(counts.size()) - 1;
  for (long sum = counts[0]; static_cast<double>(sum) <= outside;) sum += counts[static_cast<size_t>(++first)];
  for (long sum = counts.back(); static_cast<double>(sum) <= outside;) sum += counts[static_cast<size_t>(--last)];
  return {first, last};
}

}  // namespace

bool ownDepthBox(const DualBBoxFilter::Person& person, const DepthInterval& range, double trim, PersonBox* box) {
  std::vector<long> columns(static_cast<size_t>(person.depth.cols), 0);
  std::vector<long> rows(static_cast<size_t>(person.depth.rows), 0);
  long total = 0;
  for (int v = 0; v < person.depth.rows; ++v) {
    const float* row = person.depth.ptr<float>(v);
    for (int u = 0; u < person.depth.cols; ++u) {
      if (!(row[u] > range.min && row[u] < range.max)) continue;
      ++columns[static_cast<size_t>(u)];
      ++rows[static_cast<size_t>(v)];
      ++total;
    }
  }
  if (total == 0) return false;
  const double share = std::min(std::max(trim, 0.0), 0.49);  // each end keeps some depths
  const std::pair<int, int> u = trimmedSpan(columns, total, share), v = trimmedSpan(rows, total, share);
  // Pixel boxes as the detector's: x_lr, y_lr one past the last column and row.
  box->x_ul = static_cast<float>(person.area.x + u.first);
  box->x_lr = static_cast<float>(person.area.x + u.second + 1);
  box->y_ul = static_cast<float>(person.area.y + v.first);
  box->y_lr = static_cast<float>(person.area.y + v.second + 1);
  return true;
}

double keypointShareOnPerson(const DualBBoxFilter::Person& person, const PersonDetection& detection,
                             double min_score) {
  int confident = 0, on = 0;
  const cv::Rect own(0, 0, person.depth.cols, person.depth.rows);
  for (const Keypoint2d& k : detection.keypoints) {
    if (!(k.score >= min_score)) continue;
    ++confident;
    const cv::Rect near =
        cv::Rect(cvRound(k.u) - 2 - person.area.x, cvRound(k.v) - 2 - person.area.y, 5, 5) & own;
    if (!near.empty() && cv::countNonZero(person.depth(near) > 0.f) > 0) ++on;
  }
  return confident == 0 ? 1.0 : static_cast<double>(on) / confident;
}

namespace {

// COCO order of the pose network's keypoints: 15 and 16 are the ankles.
constexpr size_t kLeftAnkle = 15, kRightAnkle = 16;

// The region (image pixels) a person's body may fill, from their keypoints scored at least
// filter.joint_min_score: the box of those keypoints grown by a quarter of its size to the sides and
// up, and down to the bottom of the image unless an ankle is among them. Below the lowest confident
// keypoint the body goes on: a person so close that only their shoulders and arms are confident has
// their chest and belly there, and a person cut by the image's bottom their legs (pf2_synth
// halfsphere seed 7, xyz seed 14). Empty with fewer than filter.joint_min_count such keypoints.
cv::Rect bodyRegion(const PersonDetection& detection, const SlamOptions& options) {
  const double min_score = options.filter.joint_min_score;
  const int min_count = std::max(1, options.filter.joint_min_count);
  float u0 = std::numeric_limits<float>::max(), v0 = u0, u1 = std::numeric_limits<float>::lowest(), v1 = u1;
  int confident = 0;
  bool ankle = false;
  for (size_t k = 0; k < detection.keypoints.size(); ++k) {
    const Keypoint2d& p = detection.keypoints[k];
    if (!(p.score >= min_score)) continue;
    u0 = std::min(u0, p.u), v0 = std::min(v0, p.v), u1 = std::max(u1, p.u), v1 = std::max(v1, p.v);
    ankle = ankle || k == kLeftAnkle || k == kRightAnkle;
    ++confident;
  }
  if (confident < min_count) return {};
  const float grow_u = 0.25f * (u1 - u0), grow_v = 0.25f * (v1 - v0);
  const int bottom = ankle ? cvCeil(v1 + grow_v) + 1 : std::numeric_limits<int>::max() / 2;
  return cv::Rect(cv::Point(cvFloor(u0 - grow_u), cvFloor(v0 - grow_v)), cv::Point(cvCeil(u1 + grow_u) + 1, bottom));
}

// The median of the positive depths of `depth` inside `region` (inside = true) or outside it; 0
// when there are none.
double medianDepth(const cv::Mat& depth, const cv::Rect& region, bool inside) {
  std::vector<float> depths;
  for (int v = 0; v < depth.rows; ++v) {
    const float* row = depth.ptr<float>(v);
    for (int u = 0; u < depth.cols; ++u) {
      if (row[u] > 0.f && region.contains(cv::Point(u, v)) == inside) depths.push_back(row[u]);
    }
  }
  return upperMedian(&depths);
}

}  // namespace

std::vector<DualBBoxFilter::Person> ownParts(const std::vector<DualBBoxFilter::Person>& people,
                                             const Detections& detections, const SlamOptions& options) {
  std::vector<DualBBoxFilter::Person> own = people;
  if (!(options.human_max_outside_pose < 1.0)) return own;
  for (DualBBoxFilter::Person& person : own) {
    if (person.detection < 0 || person.detection >= static_cast<int>(detections.people.size())) continue;
    const cv::Rect claimed = (bodyRegion(detections.people[person.detection], options) - person.area.tl()) &
                             cv::Rect(0, 0, person.depth.cols, person.depth.rows);
    const int all = cv::countNonZero(person.depth > 0.f);
    if (all == 0 || claimed.empty()) continue;
    const int inside = cv::countNonZero(person.depth(claimed) > 0.f);
    if (all - inside <= options.human_max_outside_pose * all) continue;
    // Only what lies behind the body is cut off: the rest is more of the same body (a close person
    // whose confident keypoints cover a part of them) or someone in front, who has no pose of their
    // own and is placed as before.
    const double body = medianDepth(person.depth, claimed, true);
    if (!(medianDepth(person.depth, claimed, false) > body + options.human_joint_band)) continue;
    cv::Mat depth = cv::Mat::zeros(person.depth.size(), person.depth.type());
    cv::Mat mask = cv::Mat::zeros(person.mask.size(), person.mask.type());
    person.depth(claimed).copyTo(depth(claimed));
    if (mask.size() == person.depth.size()) person.mask(claimed).copyTo(mask(claimed));
    person.depth = depth;
    person.mask = mask;
  }
  return own;
}

cv::Mat bodyDepth(const DualBBoxFilter::Person& person, const BodyDepthBand& band) {
  if (band.empty()) return person.depth;
  // A person in front whose depths entered the mask would draw the fit's depth terms (and the
  // surface alignment) onto their surface.
  cv::Mat own = cv::Mat::zeros(person.depth.size(), CV_32F);
  person.depth.copyTo(own, (person.depth > band.min) & (person.depth < band.max));
  return own;
}

cv::Mat posedBodyDepth(const DualBBoxFilter::Person& person, const PersonDetection& detection,
                       const SlamOptions& options) {
  const double joints = keypointsMedianDepth(person, detection, options);
  if (!(joints > 0.0) || !(options.human_joint_band > 0.0)) return cv::Mat();
  const int limb_width = std::max(3, static_cast<int>(kSkeletonLimbWidthShare * person.box.height()));
  const cv::Mat skeleton = poseSkeleton(detection.keypoints, person.area, options.filter.joint_min_score, limb_width);
  cv::Mat own = cv::Mat::zeros(person.depth.size(), CV_32F);
  person.depth.copyTo(own, skeleton & (person.depth > joints - options.human_joint_band) &
                               (person.depth < joints + options.human_joint_band));
  return own;
}

namespace {

// A confident keypoint on a person's depth: where (on person.area) and the depth there (metres).
struct KeypointDepth {
  cv::Point at;
  float depth = 0.f;
};

std::vector<KeypointDepth> keypointDepths(const DualBBoxFilter::Person& person, const PersonDetection& detection,
                                          double min_score) {
  std::vector<KeypointDepth> keypoints;
  const cv::Rect area(0, 0, person.area.width, person.area.height);
  for (const Keypoint2d& k : detection.keypoints) {
    const cv::Point at(cvRound(k.u) - person.area.x, cvRound(k.v) - person.area.y);
    if (!(k.score >= min_score) || !area.contains(at)) continue;
    const float depth = person.depth.at<float>(at);
    if (depth > 0.f) keypoints.push_back({at, depth});
  }
  return keypoints;
}

// Clears the pixels of `behind` (CV_8U on person.area) whose depth lies no more than `reach`
// (metres) behind the depth of the nearest of `keypoints`.
void clearNearKeypointDepth(const cv::Mat& depth, const std::vector<KeypointDepth>& keypoints, float reach,
                            cv::Mat* behind) {
  for (int v = 0; v < behind->rows; ++v) {
    uint8_t* b = behind->ptr<uint8_t>(v);
    const float* z = depth.ptr<float>(v);
    for (int u = 0; u < behind->cols; ++u) {
      if (!b[u]) continue;
      const KeypointDepth* nearest = nullptr;
      long nearest_distance = 0;
      for (const KeypointDepth& k : keypoints) {
        const long du = u - k.at.x, dv = v - k.at.y, distance = du * du + dv * dv;
        if (!nearest || distance < nearest_distance) nearest = &k, nearest_distance = distance;
      }
      if (z[u] <= nearest->depth + reach) b[u] = 0;
    }
  }
}

}  // namespace

cv::Mat depthBehindBodies(const std::vector<DualBBoxFilter::Person>& people, const Detections& detections,
                          const SlamOptions& options, double margin, const cv::Size& size) {
  cv::Mat behind = cv::Mat::zeros(size, CV_8U);
  for (const DualBBoxFilter::Person& person : people) {
    if (person.detection < 0 || person.detection >= static_cast<int>(detections.people.size())) continue;
    const PersonDetection& detection = detections.people[person.detection];
    const BodyDepthBand band = keypointDepthBand(person, detection, options, cv::countNonZero(person.mask));
    if (band.empty()) continue;
    const std::vector<KeypointDepth> keypoints = keypointDepths(person, detection, options.filter.joint_min_score);
    if (keypoints.empty()) continue;
    cv::Mat far = person.depth > band.max + margin;
    if (cv::countNonZero(far) == 0) continue;
    // Within kBehindBodyReach of the body (its depths in the band), across or along the image's
    // axes: a square grown around it (a separable and cheap dilation).
    cv::Mat near_body;
    cv::dilate((person.depth > band.min) & (person.depth < band.max), near_body,
               cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * kBehindBodyReach + 1, 2 * kBehindBodyReach + 1)));
    far &= near_body;
    clearNearKeypointDepth(person.depth, keypoints, static_cast<float>(options.human_joint_band + margin), &far);
    cv::Mat area = behind(person.area);
    area |= far;
  }
  return behind;
}

namespace {

// `centres` less each one within `same_body` metres of another resting on more depths (ties: the
// earlier one stays).
std::vector<PersonCentre> withoutSecondViews(const std::vector<PersonCentre>& centres, double same_body) {
  if (!(same_body > 0.0)) return centres;
  std::vector<PersonCentre> kept;
  for (size_t i = 0; i < centres.size(); ++i) {
    bool second = false;
    for (size_t j = 0; j < centres.size() && !second; ++j) {
      const bool larger = centres[j].pixels > centres[i].pixels || (centres[j].pixels == centres[i].pixels && j < i);
      second = j != i && larger && (centres[j].p_c - centres[i].p_c).norm() < same_body;
    }
    if (!second) kept.push_back(centres[i]);
  }
  return kept;
}

}  // namespace

// Box centre at d_m (eq. 2), the box being that of the depths d_m rests on (human_box_from_depths)
// or the detector's. People whose depths cover less than human_min_area of the image get no
// centre: a sliver of a person gives a box centre far from the body.
std::vector<PersonCentre> personCentres(const DualBBoxFilter::Result& filtered, const Detections& detections,
                                        const CameraIntrinsics& K, const SlamOptions& options) {
  const double min_pixels = options.human_min_area * filtered.static_depth.total();
  std::vector<PersonCentre> centres;
  for (size_t index = 0; index < filtered.people.size(); ++index) {
    const DualBBoxFilter::Person& person = filtered.people[index];
    const bool detected = person.detection >= 0 && person.detection < static_cast<int>(detections.people.size());
    const PersonDetection* detection = detected ? &detections.people[person.detection] : nullptr;
    PersonCentre centre;
    centre.person = index;
    const double d_m = personCentreDepth(person, detection, options, &centre.pixels, &centre.band);
    if (centre.pixels == 0 || centre.pixels < min_pixels) continue;
    PersonBox box = person.box;
    if (options.human_box_from_depths) {
      const DepthInterval range = centre.band.empty() ? intervalDepths(person, detection, options)
                                                      : DepthInterval{centre.band.min, centre.band.max, true};
      ownDepthBox(person, range, options.human_box_trim, &box);  // has depths: centre.pixels > 0
    }
    centre.p_c = humanCentreInCamera(box.x_ul, box.y_ul, box.x_lr, box.y_lr, d_m, K);
    centres.push_back(centre);
  }
  return withoutSecondViews(centres, options.human_same_body);
}

}  // namespace pf2
