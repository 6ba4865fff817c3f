#include "pf2/filters/dual_bbox_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"
#include "pf2/detection/keypoint_depth.h"
#include "pf2/detection/pose_skeleton.h"
#include "image_ops.h"

namespace pf2 {
namespace {

// Per-pixel decision while filtering.
constexpr uint8_t kKept = TemporalGuard::kKept;
constexpr uint8_t kRemoved = TemporalGuard::kRemoved;  // removed but not a person's (ring outlier, temporal guard)
constexpr int kMaxPeople = 254;    // person t is stored as t + 1

// An interval widened by a margin, as floats, for pixel loops: a copy in registers (stores through
// uint8_t pointers would make the compiler reload a struct's fields on every pixel). Empty (never
// contains) when the interval is not valid.
struct DepthRange {
  float low = std::numeric_limits<float>::infinity();
  float high = -std::numeric_limits<float>::infinity();
  DepthRange() = default;
  DepthRange(const DepthInterval& interval, double margin) {
    if (!interval.valid) return;
    low = static_cast<float>(interval.min - margin);
    high = static_cast<float>(interval.max + margin);
  }
  bool contains(float depth) const { return depth > low && depth < high; }
};

void sanitize(const cv::Mat& depth, cv::Mat& out) {
  out.create(depth.size(), CV_32F);
  for (int v = 0; v < depth.rows; ++v) {
    const float* __restrict in = depth.ptr<float>(v);
    float* __restrict o = out.ptr<float>(v);
    // Comparisons with NaN are false, so this also clears NaN; bitwise & (no branches) and
    // __restrict pointers (hot loops below too) let the compiler vectorise.
    constexpr float kInf = std::numeric_limits<float>::infinity();
    for (int u = 0, u_end = depth.cols; u < u_end; ++u) o[u] = ((in[u] > 0.f) & (in[u] < kInf)) ? in[u] : 0.f;
  }
}


// A box the filter uses: confident and not empty once clipped to the image.
struct FilterBox {
  int detection;
  cv::Rect rect;      // the box
  cv::Rect ring;      // the box enlarged by lambda (Algorithm 1's background check)
  cv::Rect surround;  // the box enlarged by surround_scale (what the person stands against)
  cv::Mat mask;       // dilated backend mask on mask_area (use_mask), else empty
  cv::Rect mask_area;
  cv::Mat reach;      // mask dilated by mask_box_reach on reach_area: where the box and ring
  cv::Rect reach_area;  // rules may remove depth (empty: everywhere in the box and ring)
};

// Row v of a box's reach, offset so that it is indexed by image column u; nullptr when the row
// lies outside the reach area (nothing there may be removed). `everywhere` for a box without reach.
const uint8_t kEverywhere[1] = {255};
inline const uint8_t* reachRow(const FilterBox& b, int v, bool* everywhere) {
  *everywhere = b.reach.empty();
  if (*everywhere) return kEverywhere;
  if (v < b.reach_area.y || v >= b.reach_area.y + b.reach_area.height) return nullptr;
  return b.reach.ptr<uint8_t>(v - b.reach_area.y) - b.reach_area.x;
}

// Columns [u0, u1) of a rect clipped to the reach area (the whole rect without reach).
inline void reachColumns(const FilterBox& b, const cv::Rect& rect, int* u0, int* u1) {
  *u0 = rect.x;
  *u1 = rect.x + rect.width;
  if (b.reach.empty()) return;
  *u0 = std::max(*u0, b.reach_area.x);
  *u1 = std::min(*u1, b.reach_area.x + b.reach_area.width);
}

// Share of rect's valid depths (every second pixel and row) inside interval +- margin.
double shareInInterval(const cv::Mat& depth, const cv::Rect& rect, const DepthInterval& interval, float margin) {
  long inside = 0, valid = 0;
  const DepthRange range(interval, margin);
  for (int v = rect.y; v < rect.y + rect.height; v += 2) {
    const float* d = depth.ptr<float>(v);
    for (int u = rect.x, u_end = rect.x + rect.width; u < u_end; u += 2) {
      if (!(d[u] > 0.f)) continue;
      ++valid;
      if (range.contains(d[u])) ++inside;
    }
  }
  return valid > 0 ? static_cast<double>(inside) / valid : 0.0;
}

// Whether two intervals, each widened by margin, overlap.
bool intervalsOverlap(const DepthInterval& a, const DepthInterval& b, double margin) {
  return a.min - margin < b.max + margin && b.min - margin < a.max + margin;
}

// Two overlapping boxes whose intervals overlap may have found one person: the nearer of two
// people, who occludes the other, or the farther one seen through a gap. The box where that depth
// fills the smaller share then takes a second interval over its depths outside the first (the
// person it may have missed); both are removed. Two people side by side at one depth lose nothing:
// the second interval only adds. Boxes with a backend mask took their interval over the mask and
// get none. second_intervals[t] stays invalid for the others.
void findOccludedIntervals(const cv::Mat& depth, const std::vector<FilterBox>& boxes, const HistogramOptions& histogram,
                           float margin, const std::vector<DepthInterval>& intervals,
                           std::vector<DepthInterval>* second_intervals) {
  second_intervals->assign(boxes.size(), DepthInterval());
  cv::Mat others;  // 255 where a box's depth is not the person found twice; written per box on its rect
  for (size_t t = 0; t < boxes.size(); ++t) {
    if (!boxes[t].mask.empty()) continue;
    for (size_t s = 0; s < boxes.size() && !(*second_intervals)[t].valid; ++s) {
      const DepthInterval& mine = intervals[t];
      const DepthInterval& theirs = intervals[s];
      if (s == t || !mine.valid || !theirs.valid || (boxes[s].rect & boxes[t].rect).empty()) continue;
      if (!intervalsOverlap(mine, theirs, margin)) continue;
      if (shareInInterval(depth, boxes[t].rect, mine, margin) >= shareInInterval(depth, boxes[s].rect, theirs, margin)) {
        continue;  // the person is this box's
      }
      const cv::Rect& r = boxes[t].rect;
      // principalInterval reads the mask inside r only, so only r is written (no full-image clear).
      if (others.empty()) others.create(depth.size(), CV_8U);
      const DepthRange found(theirs, margin);
      for (int v = r.y; v < r.y + r.height; ++v) {
        const float* d = depth.ptr<float>(v);
        uint8_t* m = others.ptr<uint8_t>(v);
        for (int u = r.x, u_end = r.x + r.width; u < u_end; ++u) m[u] = found.contains(d[u]) ? 0 : 255;
      }
      (*second_intervals)[t] = principalInterval(depth, others, r, histogram, boxes[t].surround);
    }
  }
}

}  // namespace

cv::Rect scaledBoxRect(const PersonBox& box, double scale, const cv::Size& image) {
  if (box.empty() || !std::isfinite(box.x_ul) || !std::isfinite(box.y_ul) ||
      !std::isfinite(box.x_lr) || !std::isfinite(box.y_lr)) {
    return cv::Rect();
  }
  const double cu = 0.5 * (box.x_ul + box.x_lr), cv_ = 0.5 * (box.y_ul + box.y_lr);
  const double hw = 0.5 * scale * box.width(), hh = 0.5 * scale * box.height();
  auto clampTo = [](double x, int hi) {
    return static_cast<int>(std::max(0.0, std::min<double>(hi, std::floor(x + 0.5))));
  };
  const int u0 = clampTo(cu - hw, image.width), u1 = clampTo(cu + hw, image.width);
  const int v0 = clampTo(cv_ - hh, image.height), v1 = clampTo(cv_ + hh, image.height);
  if (u1 <= u0 || v1 <= v0) return cv::Rect();
  return cv::Rect(u0, v0, u1 - u0, v1 - v0);
}

DepthInterval principalInterval(const cv::Mat& depth, const cv::Mat& mask, const cv::Rect& roi,
                                const HistogramOptions& options, const cv::Rect& surround) {
  DepthInterval interval;
  const cv::Rect image(0, 0, depth.cols, depth.rows);
  const cv::Rect r = roi & image;
  if (r.empty() || options.bin_width <= 0 || options.max_depth <= 0) return interval;
  const int bins = static_cast<int>(std::ceil(options.max_depth / options.bin_width));
  const float inv_bin = static_cast<float>(1.0 / options.bin_width);
  const float max_depth = static_cast<float>(options.max_depth);
  const int stride = std::max(1, options.stride);
  // Counts the valid depths of every step-th pixel of row v in [u0, u1) under `under` (if any);
  // returns how many pixels it looked at, with depth or not.
  auto countRow = [&](int v, int u0, int u1, int step, const cv::Mat& under, std::vector<int>* counts) {
    const float* d = depth.ptr<float>(v);
    const uint8_t* m = under.empty() ? nullptr : under.ptr<uint8_t>(v);
    long looked = 0;
    for (int u = u0; u < u1; u += step) {
      if (m && !m[u]) continue;
      ++looked;
      const float z = d[u];
      if (!(z > 0.f && z < max_depth)) continue;  // also rejects NaN
      ++(*counts)[std::min(bins - 1, static_cast<int>(z * inv_bin))];
    }
    return looked;
  };
  std::vector<int> roi_counts(bins, 0);
  long roi_pixels = 0;
  for (int v = r.y; v < r.y + r.height; v += stride) roi_pixels += countRow(v, r.x, r.x + r.width, stride, mask, &roi_counts);
  std::vector<double> counts(roi_counts.begin(), roi_counts.end());
  const cv::Rect around = surround & image;
  if (options.surround_weight > 0 && !around.empty()) {
    // Only the density matters here: every second pixel and row is enough.
    const int step = 2 * stride;
    std::vector<int> background(bins, 0);
    long around_pixels = 0;
    for (int v = around.y; v < around.y + around.height; v += step) {
      if (v >= r.y && v < r.y + r.height) {  // the rows beside roi: left and right of it
        around_pixels += countRow(v, around.x, std::min(r.x, around.x + around.width), step, cv::Mat(), &background);
        around_pixels += countRow(v, std::max(around.x, r.x + r.width), around.x + around.width, step, cv::Mat(), &background);
      } else {
        around_pixels += countRow(v, around.x, around.x + around.width, step, cv::Mat(), &background);
      }
    }
    if (around_pixels > 0) {
      // Density around x the pixels looked at in roi (a mask's pixels only, with a mask).
      const double weight = options.surround_weight * static_cast<double>(roi_pixels) / around_pixels;
      for (int b = 0; b < bins; ++b) counts[b] = std::max(0.0, counts[b] - weight * background[b]);
    }
  }
  const int window = std::max(1, std::min(bins, static_cast<int>(std::lround(options.window / options.bin_width))));
  std::vector<double> sums(bins - window + 1, 0.0);
  double running = 0;
  for (int b = 0; b < bins; ++b) {
    running += counts[b];
    if (b >= window) running -= counts[b - window];
    if (b >= window - 1) sums[b - window + 1] = running;
  }
  const double best = *std::max_element(sums.begin(), sums.end());
  if (best <= 0) return interval;
  // The nearest window good enough, moved to the top of the hill it starts on.
  const double threshold = options.near_preference * best;
  size_t a = 0;
  while (a < sums.size() && sums[a] < threshold) ++a;
  size_t chosen = a;
  for (size_t b = a; b < sums.size() && sums[b] >= threshold; ++b) {
    if (sums[b] > sums[chosen]) chosen = b;
  }
  const double grow = options.grow_fraction * sums[chosen] / window;
  int lo = static_cast<int>(chosen), hi = static_cast<int>(chosen) + window - 1;
  while (lo > 0 && counts[lo - 1] > 0 && counts[lo - 1] >= grow) --lo;
  while (hi < bins - 1 && counts[hi + 1] > 0 && counts[hi + 1] >= grow) ++hi;
  // Trim empty bins at the window's ends so that the interval hugs the data.
  while (lo < hi && counts[lo] == 0) ++lo;
  while (hi > lo && counts[hi] == 0) --hi;
  interval.min = lo * options.bin_width;
  interval.max = (hi + 1) * options.bin_width;
  interval.valid = true;
  return interval;
}

namespace {

// CV_8U image of depth's size, 255 where both depth and prediction are measured and
// test(depth, predicted) holds. Bitwise & (no branches) so that the loop vectorises; NaN compares
// false, so it never passes.
template <typename Test>
cv::Mat compareWithPrediction(const cv::Mat& depth, const cv::Mat& prediction, Test test) {
  cv::Mat mask(depth.size(), CV_8U);
  for (int v = 0; v < depth.rows; ++v) {
    const float* d = depth.ptr<float>(v);
    const float* p = prediction.ptr<float>(v);
    uint8_t* m = mask.ptr<uint8_t>(v);
    for (int u = 0, u_end = depth.cols; u < u_end; ++u) {
      m[u] = static_cast<uint8_t>(-static_cast<int>((p[u] > 0.f) & (d[u] > 0.f) & test(d[u], p[u])));
    }
  }
  return mask;
}

}  // namespace

cv::Mat PredictedDepthEvidence::dynamicMask(const cv::Mat& depth) {
  if (prediction_.empty()) return cv::Mat::zeros(depth.size(), CV_8U);
  if (prediction_.size() != depth.size() || prediction_.type() != CV_32F) {
    throw Error("PredictedDepthEvidence: prediction is not a CV_32F image of the depth's size");
  }
  const float margin = static_cast<float>(margin_);
  cv::Mat mask = compareWithPrediction(depth, prediction_, [margin](float d, float p) { return d < p - margin; });
  if (opening_radius_ > 0) {
    const int size = 2 * opening_radius_ + 1;
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN,
                     cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size, size)));
  }
  return mask;
}

namespace {

// 255 where the point of a depth pixel lies within margin (plus 1 % of its depth) of plane_c. A
// pixel's point is z r with the ray r = ((u - cx) / fx, (v - cy) / fy, 1), so its signed distance
// z (n . r) + offset is linear in u along a row.
cv::Mat nearPlane(const cv::Mat& depth, const Eigen::Hyperplane<double, 3>& plane_c, const CameraIntrinsics& k,
                  double margin) {
  if (k.width != depth.cols || k.height != depth.rows) {
    throw Error("PredictedDepthEvidence: the static plane's intrinsics are not of the depth's size");
  }
  const Eigen::Vector3d& n = plane_c.normal();
  const float offset = static_cast<float>(plane_c.offset());
  const float along_u = static_cast<float>(n.x() / k.fx);
  const float tolerance = static_cast<float>(margin);
  cv::Mat mask(depth.size(), CV_8U);
  for (int v = 0; v < depth.rows; ++v) {
    const float at_u0 = static_cast<float>(-n.x() * k.cx / k.fx + n.y() * (v - k.cy) / k.fy + n.z());
    const float* d = depth.ptr<float>(v);
    uint8_t* m = mask.ptr<uint8_t>(v);
    for (int u = 0, u_end = depth.cols; u < u_end; ++u) {
      const float distance = d[u] * (at_u0 + along_u * static_cast<float>(u)) + offset;
      m[u] = static_cast<uint8_t>(-static_cast<int>((d[u] > 0.f) & (std::fabs(distance) < tolerance + 0.01f * d[u])));
    }
  }
  return mask;
}

}  // namespace

cv::Mat PredictedDepthEvidence::staticMask(const cv::Mat& depth) {
  cv::Mat known;
  if (!prediction_.empty() && static_margin_ > 0.0) {
    const float margin = static_cast<float>(static_margin_);
    known = compareWithPrediction(depth, prediction_,
                                  [margin](float d, float p) { return std::fabs(d - p) < margin + 0.01f * d; });
  }
  if (plane_c_ && plane_margin_ > 0.0) {
    const cv::Mat on_plane = nearPlane(depth, *plane_c_, plane_intrinsics_, plane_margin_);
    if (known.empty()) known = on_plane;
    else known |= on_plane;
  }
  return known;
}

cv::Mat DualBBoxFilter::Person::fullDepth(const cv::Size& image) const {
  cv::Mat full = cv::Mat::zeros(image, CV_32F);
  if (!depth.empty()) depth.copyTo(full(area));
  return full;
}

cv::Mat DualBBoxFilter::Person::fullMask(const cv::Size& image) const {
  cv::Mat full = cv::Mat::zeros(image, CV_8U);
  if (!mask.empty()) mask.copyTo(full(area));
  return full;
}

DualBBoxFilter::DualBBoxFilter(const Options& options)
    : options_(options),
      temporal_(options.temporal_guard),
      depth_gate_(options.depth_gate),
      geometric_(options.geometric_addition) {}

void DualBBoxFilter::reset() {
  temporal_.reset();
  geometric_.reset();
}

namespace {

// Algorithm 1, input: the confident boxes clipped to the image (at most kMaxPeople), with their
// ring and surround, and with use_mask their dilated mask and reach.
std::vector<FilterBox> selectBoxes(const Detections& detections, const DualBBoxFilter::Options& o,
                                   const cv::Size& size) {
  std::vector<FilterBox> boxes;
  for (size_t i = 0; i < detections.people.size() && boxes.size() < static_cast<size_t>(kMaxPeople); ++i) {
    const PersonDetection& p = detections.people[i];
    if (!(p.score > o.min_confidence)) continue;
    FilterBox b{static_cast<int>(i), scaledBoxRect(p.box, 1.0, size), scaledBoxRect(p.box, o.box_scale, size),
                scaledBoxRect(p.box, o.surround_scale, size), {}, {}, {}, {}};
    if (o.use_mask && !p.mask.empty() && p.mask.size() == size && p.mask.type() == CV_8U) {
      b.mask = dilatedOnArea(p.mask, o.mask_dilation, &b.mask_area);
      if (o.mask_box_reach > 0) b.reach = dilatedOnArea(p.mask, o.mask_box_reach, &b.reach_area);
    }
    if (b.rect.empty() && b.mask.empty()) continue;
    boxes.push_back(std::move(b));
  }
  return boxes;
}

// Algorithm 1, scene separation: (b_min, b_max) from D_b's histogram taken outside every box;
// `outside` becomes 255 outside every box and 0 inside.
DepthInterval backgroundInterval(const cv::Mat& depth, const std::vector<FilterBox>& boxes,
                                 const HistogramOptions& histogram, cv::Mat& outside) {
  const cv::Size size = depth.size();
  outside.create(size, CV_8U);
  outside.setTo(255);
  for (const FilterBox& b : boxes) outside(b.rect).setTo(0);
  return principalInterval(depth, outside, cv::Rect(0, 0, size.width, size.height), histogram);
}

// The median measured depth under a person's keypoints scored at least options.joint_min_score,
// or 0 when fewer than options.joint_min_count of them (or joint_min_count is 0).
double jointDepth(const cv::Mat& depth, const PersonDetection& person, const DualBBoxFilter::Options& options) {
  if (options.joint_min_count <= 0) return 0.0;
  return medianDepthAtKeypoints(depth, cv::Point(0, 0), person.keypoints, options.joint_min_score,
                                options.joint_min_count, options.human_histogram.max_depth);
}

// The principal interval of the mask's pixels within half a window of `depth_m`.
DepthInterval intervalNear(const cv::Mat& depth, const cv::Mat& mask, const cv::Rect& roi, double depth_m,
                           const HistogramOptions& histogram) {
  const float lo = static_cast<float>(depth_m - 0.5 * histogram.window);
  const float hi = static_cast<float>(depth_m + 0.5 * histogram.window);
  cv::Mat near = cv::Mat::zeros(depth.size(), CV_8U);
  for (int v = roi.y; v < roi.y + roi.height; ++v) {
    const float* d = depth.ptr<float>(v);
    const uint8_t* m = mask.ptr<uint8_t>(v);
    uint8_t* out = near.ptr<uint8_t>(v);
    for (int u = roi.x; u < roi.x + roi.width; ++u) out[u] = (m[u] && d[u] >= lo && d[u] <= hi) ? 255 : 0;
  }
  return principalInterval(depth, near, roi, histogram);
}

// True when another box overlapping box t found an interval overlapping t's (margins included).
bool sharesAnotherPersonsDepth(size_t t, const std::vector<FilterBox>& boxes,
                               const std::vector<DepthInterval>& intervals, double margin) {
  for (size_t s = 0; s < boxes.size(); ++s) {
    if (s == t || !intervals[s].valid || (boxes[s].rect & boxes[t].rect).empty()) continue;
    if (intervalsOverlap(intervals[t], intervals[s], margin)) return true;
  }
  return false;
}

// Algorithm 1, (h_min, h_max) of each box: over the backend mask where it counts a depth (use_mask),
// else over the box with the surround's density taken off. A mask's principal depth can be a
// nearer person's: a mask two people share is split by the nearest keypoint, which hands the
// person behind the pixels of whoever stands in front around their joints, and the near person's
// pixels, many at their size in the image, outweigh the far one's. So when a masked person's
// interval is also an overlapping person's and the depth under their confident joints lies outside
// it (beyond human_margin), it is taken again over the mask's pixels near the joints' depth. (The
// joints alone are no proof: those of a near person cut by the border often land behind them.)
std::vector<DepthInterval> humanIntervals(const cv::Mat& depth, const std::vector<FilterBox>& boxes,
                                          const Detections& detections, const DualBBoxFilter::Options& options) {
  std::vector<DepthInterval> intervals(boxes.size());
  const HistogramOptions& histogram = options.human_histogram;
  for (size_t t = 0; t < boxes.size(); ++t) {
    const FilterBox& b = boxes[t];
    if (!b.mask.empty()) {
      intervals[t] = principalInterval(depth, detections.people[b.detection].mask, b.rect, histogram);
      if (intervals[t].valid) continue;
    }
    intervals[t] = principalInterval(depth, cv::Mat(), b.rect, histogram, b.surround);
  }
  std::vector<DepthInterval> taken = intervals;
  for (size_t t = 0; t < boxes.size(); ++t) {
    if (boxes[t].mask.empty() || !taken[t].valid || !sharesAnotherPersonsDepth(t, boxes, taken, options.human_margin)) {
      continue;
    }
    const PersonDetection& person = detections.people[boxes[t].detection];
    const double joints = jointDepth(depth, person, options);
    if (joints <= 0.0 || taken[t].contains(joints, options.human_margin)) continue;
    const DepthInterval at_joints = intervalNear(depth, person.mask, boxes[t].rect, joints, histogram);
    if (at_joints.valid) intervals[t] = at_joints;
  }
  return intervals;
}

// Algorithm 1, scene separation: box t's pixels (within its reach) in its interval or second
// interval, and with use_mask its dilated mask's pixels, become person t (state t + 1). Returns
// where each person's pixels can be.
std::vector<cv::Rect> labelPeople(const cv::Mat& depth, const std::vector<FilterBox>& boxes,
                                  const std::vector<DepthInterval>& intervals,
                                  const std::vector<DepthInterval>& second_intervals, float human_margin,
                                  cv::Mat& state) {
  std::vector<cv::Rect> areas(boxes.size());
  for (size_t t = 0; t < boxes.size(); ++t) {
    const FilterBox& b = boxes[t];
    const uint8_t label = static_cast<uint8_t>(t + 1);
    const DepthRange h(intervals[t], human_margin), h2(second_intervals[t], human_margin);
    areas[t] = b.rect;
    int u_begin, u_end;
    reachColumns(b, b.rect, &u_begin, &u_end);
    for (int v = b.rect.y; v < b.rect.y + b.rect.height; ++v) {
      const float* d = depth.ptr<float>(v);
      uint8_t* s = state.ptr<uint8_t>(v);
      bool everywhere;
      const uint8_t* r = reachRow(b, v, &everywhere);
      if (!r) continue;
      for (int u = u_begin; u < u_end; ++u) {
        if ((everywhere || r[u]) && s[u] == kKept && d[u] > 0.f && (h.contains(d[u]) || h2.contains(d[u]))) {
          s[u] = label;
        }
      }
    }
    if (!b.mask.empty()) {
      const cv::Rect& a = b.mask_area;
      areas[t] |= a;
      for (int v = 0; v < a.height; ++v) {
        const float* d = depth.ptr<float>(v + a.y) + a.x;
        const uint8_t* m = b.mask.ptr<uint8_t>(v);
        uint8_t* s = state.ptr<uint8_t>(v + a.y) + a.x;
        for (int u = 0, u_end = a.width; u < u_end; ++u) {
          if (m[u] && s[u] == kKept && d[u] > 0.f) s[u] = label;
        }
      }
    }
  }
  return areas;
}

// Gives back the removed pixels set in `pixels` that no person's (dilated) mask covers: the box,
// ring or temporal rule took them, an addition found them static. A mask's own pixels stay
// removed: its blurred edges are often apart from the person's depth and unknown to the
// prediction (gating them in the depth gate too kept 1-2 points more static depth but removed
// 1-1.5 points less of the people).
void keepOutsideMasks(cv::Mat pixels, const std::vector<FilterBox>& boxes, cv::Mat& state) {
  if (pixels.empty()) return;
  for (const FilterBox& b : boxes) {
    if (!b.mask.empty()) pixels(b.mask_area).setTo(0, b.mask);
  }
  state.setTo(kKept, pixels);
}

// `pixels` (known static) without the people the segmenter missed but the pose network found (no
// mask, at least joint_min_count keypoints scored joint_min_score): on their skeleton, limbs drawn
// kSkeletonLimbWidthShare of the box's height wide and the torso filled, the pixels their box rule
// labelled stay removed. A person seated since the first keyframe is "static" to the prediction,
// and without this the static evidence gave them back to the map (pf2_synth rpy, a seated person
// in dark clothes in frames 48-57: 27 -> 92 % of them removed; docs/BENCHMARKS.md).
cv::Mat withoutPosedPeople(cv::Mat pixels, const std::vector<FilterBox>& boxes, const Detections& detections,
                           const DualBBoxFilter::Options& o, const cv::Mat& state) {
  if (pixels.empty()) return pixels;
  for (size_t t = 0; t < boxes.size(); ++t) {
    const FilterBox& b = boxes[t];
    const std::vector<Keypoint2d>& k = detections.people[b.detection].keypoints;
    if (!b.mask.empty()) continue;
    int confident = 0;
    for (const Keypoint2d& p : k) confident += p.score >= o.joint_min_score;
    if (confident < std::max(1, o.joint_min_count)) continue;
    // Drawn on the box alone (lines leaving it are clipped): only the box's labels are read.
    const int thickness = std::max(3, static_cast<int>(kSkeletonLimbWidthShare * b.rect.height));
    const cv::Mat skeleton = poseSkeleton(k, b.rect, o.joint_min_score, thickness);
    const uint8_t label = static_cast<uint8_t>(t + 1);
    cv::Mat mine = (state(b.rect) == label) & skeleton;
    pixels(b.rect).setTo(0, mine);
  }
  return pixels;
}

// The known static depth under each person's dilated mask that an earlier rule removed and that
// lies more than `margin` behind their interval, or in the ring the dilation added around the
// segmenter's own mask (CV_8U, 255); empty when there is none. The ring catches the mixed pixels
// at a person's outline; where the prediction confirms the depth there, it is the background
// (pf2_synth: 0.3-0.5 points more static depth kept, 0.03-0.09 fewer of the people removed).
cv::Mat staticUnderMasks(const cv::Mat& depth, const cv::Mat& known, const std::vector<FilterBox>& boxes,
                         const Detections& detections, const std::vector<DepthInterval>& intervals, float margin,
                         const cv::Mat& state) {
  cv::Mat kept;
  for (size_t t = 0; t < boxes.size(); ++t) {
    const FilterBox& b = boxes[t];
    if (b.mask.empty() || !intervals[t].valid) continue;
    if (kept.empty()) kept = cv::Mat::zeros(depth.size(), CV_8U);
    const float far = static_cast<float>(intervals[t].max) + margin;
    const cv::Rect& a = b.mask_area;
    const cv::Mat& segmented = detections.people[b.detection].mask;  // undilated, image-sized
    for (int v = 0; v < a.height; ++v) {
      const float* d = depth.ptr<float>(v + a.y) + a.x;
      const uint8_t* k = known.ptr<uint8_t>(v + a.y) + a.x;
      const uint8_t* s = state.ptr<uint8_t>(v + a.y) + a.x;
      const uint8_t* m = b.mask.ptr<uint8_t>(v);
      const uint8_t* own = segmented.ptr<uint8_t>(v + a.y) + a.x;
      uint8_t* out = kept.ptr<uint8_t>(v + a.y) + a.x;
      for (int u = 0; u < a.width; ++u) {
        if (m[u] && k[u] && s[u] != kKept && (d[u] > far || !own[u])) out[u] = 255;
      }
    }
  }
  return kept;
}

// What the box, ring and temporal rules removed outside every person's dilated mask (CV_8U, 255):
// the pixels removed in `state` apart from the masks, the labels of people without a mask (their
// box is all there is of them) and what `dynamic` (may be empty) marks.
cv::Mat removedOutsideMasks(const cv::Mat& state, const std::vector<FilterBox>& boxes, const cv::Mat& dynamic) {
  cv::Mat outside = state != kKept;
  for (size_t t = 0; t < boxes.size(); ++t) {
    const FilterBox& b = boxes[t];
    if (!b.mask.empty()) {
      outside(b.mask_area).setTo(0, b.mask);
    } else {
      outside(b.rect).setTo(0, state(b.rect) == static_cast<uint8_t>(t + 1));
    }
  }
  if (!dynamic.empty()) outside.setTo(0, dynamic);
  return outside;
}

// The temporal guard's spared pixels (a surface that was there before, TemporalGuard::spared) that
// are still removed in `state` and not marked by `dynamic` (may be empty): for the map alone.
cv::Mat sparedStillRemoved(const cv::Mat& spared, const cv::Mat& state, const cv::Mat& dynamic) {
  cv::Mat still = spared & (state == kRemoved);
  if (!dynamic.empty()) still.setTo(0, dynamic);
  return still;
}

// D_b keeps the depth at `pixels` (CV_8U, 255), which are reported as kept for the map only.
void keepForMapOnly(const cv::Mat& depth, const cv::Mat& pixels, DualBBoxFilter::Result* result) {
  depth.copyTo(result->static_depth, pixels);
  result->removed.setTo(0, pixels);
  result->kept_for_map_only = pixels;
}

// The people's depth the gate compares with: each raw backend mask's pixels whose depth lies in
// the person's interval (the mask's blurred edges can take in the wall behind a person).
cv::Mat personCore(const cv::Mat& depth, const std::vector<FilterBox>& boxes, const Detections& detections,
                   const std::vector<DepthInterval>& intervals, float human_margin) {
  cv::Mat core = cv::Mat::zeros(depth.size(), CV_8U);
  for (size_t t = 0; t < boxes.size(); ++t) {
    const FilterBox& b = boxes[t];
    if (b.mask.empty()) continue;
    const DepthRange h(intervals[t], human_margin);
    const cv::Mat& mask = detections.people[b.detection].mask;
    const cv::Rect& a = b.mask_area;
    for (int v = a.y; v < a.y + a.height; ++v) {
      const float* d = depth.ptr<float>(v);
      const uint8_t* m = mask.ptr<uint8_t>(v);
      uint8_t* c = core.ptr<uint8_t>(v);
      for (int u = a.x; u < a.x + a.width; ++u) {
        if (m[u] && h.contains(d[u])) c[u] = 255;
      }
    }
  }
  return core;
}

// Algorithm 1 lines 10-11: in the ring between each box and its lambda-enlarged box (outside every
// box, within the reach), depth unlike the background (b_min, b_max) +- margin is removed.
void removeRingOutliers(const cv::Mat& depth, const std::vector<FilterBox>& boxes, const DepthInterval& interval,
                        double margin, const cv::Mat& outside, cv::Mat& state) {
  const DepthRange background(interval, margin);
  for (const FilterBox& b : boxes) {
    int u_begin, u_end;
    reachColumns(b, b.ring, &u_begin, &u_end);
    for (int v = b.ring.y; v < b.ring.y + b.ring.height; ++v) {
      const float* d = depth.ptr<float>(v);
      const uint8_t* out = outside.ptr<uint8_t>(v);
      uint8_t* s = state.ptr<uint8_t>(v);
      bool everywhere;
      const uint8_t* r = reachRow(b, v, &everywhere);
      if (!r) continue;
      for (int u = u_begin; u < u_end; ++u) {
        if ((everywhere || r[u]) && s[u] == kKept && out[u] && d[u] > 0.f && !background.contains(d[u])) {
          s[u] = kRemoved;
        }
      }
    }
  }
}

// Algorithm 1, output D_b (and the removed mask), in one pass over the image: the kept pixels that
// the geometric addition's mask (when not empty) does not mark dynamic.
void writeStaticDepth(const cv::Mat& depth, const cv::Mat& state, const cv::Mat& dynamic,
                      DualBBoxFilter::Result* result) {
  const cv::Size size = depth.size();
  result->static_depth.create(size, CV_32F);
  result->removed.create(size, CV_8U);
  for (int v = 0; v < size.height; ++v) {
    const float* __restrict d = depth.ptr<float>(v);
    const uint8_t* __restrict s = state.ptr<uint8_t>(v);
    const uint8_t* __restrict dyn = dynamic.empty() ? nullptr : dynamic.ptr<uint8_t>(v);
    float* __restrict out = result->static_depth.ptr<float>(v);
    uint8_t* __restrict removed = result->removed.ptr<uint8_t>(v);
    if (dyn) {
      for (int u = 0, u_end = size.width; u < u_end; ++u) {
        const bool kept = (s[u] == kKept) & (dyn[u] == 0);
        out[u] = kept ? d[u] : 0.f;
        removed[u] = static_cast<uint8_t>(-static_cast<int>(!kept & (d[u] > 0.f)));
      }
    } else {
      for (int u = 0, u_end = size.width; u < u_end; ++u) {
        const bool kept = s[u] == kKept;
        out[u] = kept ? d[u] : 0.f;
        removed[u] = static_cast<uint8_t>(-static_cast<int>(!kept & (d[u] > 0.f)));
      }
    }
  }
}

// Algorithm 1, output D_h^t: each person's box, interval and area, and the pixels labelled t + 1,
// in one pass over each person's area.
void collectPeople(const cv::Mat& depth, const cv::Mat& state, const std::vector<FilterBox>& boxes,
                   const std::vector<DepthInterval>& intervals, const std::vector<cv::Rect>& areas,
                   std::vector<DualBBoxFilter::Person>* people) {
  people->resize(boxes.size());
  for (size_t t = 0; t < boxes.size(); ++t) {
    DualBBoxFilter::Person& p = (*people)[t];
    p.detection = boxes[t].detection;
    const cv::Rect& r = boxes[t].rect;
    p.box = PersonBox{static_cast<float>(r.x), static_cast<float>(r.y), static_cast<float>(r.x + r.width),
                      static_cast<float>(r.y + r.height)};
    p.interval = intervals[t];
    p.area = areas[t];
    const cv::Rect& a = p.area;
    p.mask = cv::Mat::zeros(a.size(), CV_8U);
    p.depth = cv::Mat::zeros(a.size(), CV_32F);
    const uint8_t label = static_cast<uint8_t>(t + 1);
    for (int v = 0; v < a.height; ++v) {
      const float* d = depth.ptr<float>(v + a.y) + a.x;
      const uint8_t* s = state.ptr<uint8_t>(v + a.y) + a.x;
      uint8_t* m = p.mask.ptr<uint8_t>(v);
      float* pd = p.depth.ptr<float>(v);
      for (int u = 0, u_end = a.width; u < u_end; ++u) {
        if (s[u] == label) {
          m[u] = 255;
          pd[u] = d[u];
        }
      }
    }
  }
}

// The half-resolution grid of the temporal addition: every second pixel and row.

}  // namespace

const CameraIntrinsics& DualBBoxFilter::temporalIntrinsics(const cv::Mat& depth) const {
  if (!intrinsics_) throw Error("DualBBoxFilter: the temporal addition needs the camera intrinsics (setIntrinsics)");
  if (intrinsics_->width != depth.cols || intrinsics_->height != depth.rows) {
    throw Error("DualBBoxFilter: intrinsics of " + std::to_string(intrinsics_->width) + "x" +
                std::to_string(intrinsics_->height) + " for a depth image of " + std::to_string(depth.cols) + "x" +
                std::to_string(depth.rows));
  }
  return *intrinsics_;
}

// Algorithm 1 (scene separation, the ring, the outputs) with the additions, step by step.
DualBBoxFilter::Result DualBBoxFilter::filter(const cv::Mat& depth_in, const Detections& detections,
                                              const Eigen::Isometry3d& T_cur_prev) {
  if (depth_in.empty() || depth_in.type() != CV_32F) {
    throw Error("DualBBoxFilter: depth must be a non-empty CV_32F image (metres)");
  }
  sanitize(depth_in, depth_);
  const cv::Mat& depth = depth_;
  const Options& o = options_;
  const std::vector<FilterBox> boxes = selectBoxes(detections, o, depth.size());
  Result result;
  result.background = backgroundInterval(depth, boxes, o.background_histogram, outside_);
  state_.create(depth.size(), CV_8U);
  state_.setTo(0);
  const std::vector<DepthInterval> intervals = humanIntervals(depth, boxes, detections, o);
  const float human_margin = static_cast<float>(o.human_margin);
  std::vector<DepthInterval> second_intervals(boxes.size());
  if (o.separate_occlusions) {
    findOccludedIntervals(depth, boxes, o.human_histogram, human_margin, intervals, &second_intervals);
  }
  const std::vector<cv::Rect> areas = labelPeople(depth, boxes, intervals, second_intervals, human_margin, state_);
  removeRingOutliers(depth, boxes, result.background, o.background_margin, outside_, state_);
  const cv::Rect guarded_area = o.temporal ? temporal_.guard(depth, temporalIntrinsics(depth), T_cur_prev, state_)
                                           : cv::Rect();
  if (o.use_mask && o.depth_gate.radius > 0) {  // the local depth gate: apart from the people's depth
    keepOutsideMasks(depth_gate_.outsidePeople(depth, personCore(depth, boxes, detections, intervals, human_margin)),
                     boxes, state_);
  }
  // Without the geometric addition, the evidence still confirms the detector's sure candidates and
  // reports what it knows as static (PersonRemoval: the floor plane; no prediction).
  const cv::Mat dynamic = geometric_.dynamicMask(depth, detections, o.min_confidence, o.mask_dilation, o.geometric);
  const cv::Mat known = dynamic.empty() ? cv::Mat() : geometric_.knownStatic(depth, dynamic);
  cv::Mat map_only = o.keep_static_behind_masks && !known.empty()
                         ? staticUnderMasks(depth, known, boxes, detections, intervals, human_margin, state_)
                         : cv::Mat();
  if (!known.empty()) keepOutsideMasks(withoutPosedPeople(known, boxes, detections, o, state_), boxes, state_);
  writeStaticDepth(depth, state_, dynamic, &result);
  if (o.outside_masks_tracker_only) {
    const cv::Mat outside = removedOutsideMasks(state_, boxes, dynamic);
    map_only = map_only.empty() ? outside : (map_only | outside);
  }
  if (o.temporal && o.temporal_guard.static_tolerance > 0.0) {
    const cv::Mat spared = sparedStillRemoved(temporal_.spared(), state_, dynamic);
    map_only = map_only.empty() ? spared : (map_only | spared);
  }
  collectPeople(depth, state_, boxes, intervals, areas, &result.people);
  if (o.temporal) temporal_.carry(depth, state_, areas, guarded_area);
  // After the people and the temporal guard: they still see these pixels as the person's.
  if (!map_only.empty()) keepForMapOnly(depth, map_only, &result);
  return result;
}

}  // namespace pf2
