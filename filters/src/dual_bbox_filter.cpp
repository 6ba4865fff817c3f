#include "pf2/filters/dual_bbox_filter.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

// Per-pixel decision while filtering.
constexpr uint8_t kKept = 0;
constexpr uint8_t kRemoved = 255;  // removed but not a person's (ring outlier, temporal guard)
constexpr int kMaxPeople = 254;    // person t is stored as t + 1
constexpr int kMaxTemporalRadius = 40;  // half-resolution cells: 80 px, a person at 0.25 m

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

// The mask's pixels dilated by `radius` (a disc), as an image of `area`'s size: the mask's
// bounding box grown by radius, clipped to the image. Empty (and area empty) for an empty mask.
cv::Mat dilatedOnArea(const cv::Mat& mask, int radius, cv::Rect* area) {
  const cv::Rect bounds = cv::boundingRect(mask);
  if (bounds.empty()) {
    *area = cv::Rect();
    return cv::Mat();
  }
  const int r = std::max(0, radius);
  *area = cv::Rect(bounds.x - r, bounds.y - r, bounds.width + 2 * r, bounds.height + 2 * r) &
          cv::Rect(0, 0, mask.cols, mask.rows);
  cv::Mat binary = mask(*area) > 0;
  if (r > 0) {
    cv::dilate(binary, binary, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(2 * r + 1, 2 * r + 1)),
               cv::Point(-1, -1), 1, cv::BORDER_CONSTANT | cv::BORDER_ISOLATED, cv::Scalar(0));
  }
  return binary;
}

// Forward-warps depth (and a companion CV_8U image) into another view, nearest point wins. The
// outputs are reused when they already have the right size. Only source pixels inside source_area
// are read (the caller knows the rest is zero). Returns the bounds of what landed.
cv::Rect warpWithCompanion(const cv::Mat& depth_src, const cv::Mat& companion_src,
                           const CameraIntrinsics& K, const Eigen::Isometry3d& T_dst_src,
                           const cv::Rect& source_area, cv::Mat* depth_dst, cv::Mat* companion_dst) {
  depth_dst->create(depth_src.size(), CV_32F);
  depth_dst->setTo(0);
  if (companion_dst) {
    companion_dst->create(depth_src.size(), CV_8U);
    companion_dst->setTo(0);
  }
  int u_min = depth_src.cols, v_min = depth_src.rows, u_max = -1, v_max = -1;
  const Eigen::Matrix3f R = T_dst_src.linear().cast<float>();
  const Eigen::Vector3f t = T_dst_src.translation().cast<float>();
  const float fx = K.fx, fy = K.fy, cx = K.cx, cy = K.cy;
  // p_dst = z * (R (x_n, y_n, 1)) + t with x_n, y_n the normalised coordinates: the rotated ray is
  // a column term plus a row term, computed once per column and per row.
  std::vector<Eigen::Vector3f> column_ray(depth_src.cols);
  for (int u = 0, u_end = depth_src.cols; u < u_end; ++u) column_ray[u] = R.col(0) * ((u - cx) / fx);
  const int width = depth_src.cols, height = depth_src.rows;
  const cv::Rect area = source_area & cv::Rect(0, 0, width, height);
  for (int v = area.y; v < area.y + area.height; ++v) {
    const float* row = depth_src.ptr<float>(v);
    const Eigen::Vector3f row_ray = R.col(1) * ((v - cy) / fy) + R.col(2);
    for (int u = area.x, u_end = area.x + area.width; u < u_end; ++u) {
      const float z = row[u];
      if (!(z > 0.f)) continue;
      const Eigen::Vector3f p_dst = z * (column_ray[u] + row_ray) + t;
      if (!(p_dst.z() > 0.f)) continue;
      const float uf = fx * p_dst.x() / p_dst.z() + cx + 0.5f;
      const float vf = fy * p_dst.y() / p_dst.z() + cy + 0.5f;
      if (!(uf >= 0.f && vf >= 0.f && uf < width && vf < height)) continue;  // also rejects NaN
      const int ud = static_cast<int>(uf), vd = static_cast<int>(vf);  // round to nearest
      u_min = std::min(u_min, ud);
      u_max = std::max(u_max, ud);
      v_min = std::min(v_min, vd);
      v_max = std::max(v_max, vd);
      float& target = depth_dst->at<float>(vd, ud);
      if (target == 0.f || p_dst.z() < target) {
        target = p_dst.z();
        if (companion_dst) companion_dst->at<uint8_t>(vd, ud) = companion_src.at<uint8_t>(v, u);
      }
    }
  }
  return u_max < 0 ? cv::Rect() : cv::Rect(u_min, v_min, u_max - u_min + 1, v_max - v_min + 1);
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
      if (mine.min - margin >= theirs.max + margin || theirs.min - margin >= mine.max + margin) continue;
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

cv::Mat PredictedDepthEvidence::dynamicMask(const cv::Mat& depth) {
  if (prediction_.empty()) return cv::Mat::zeros(depth.size(), CV_8U);
  if (prediction_.size() != depth.size() || prediction_.type() != CV_32F) {
    throw Error("PredictedDepthEvidence: prediction is not a CV_32F image of the depth's size");
  }
  cv::Mat mask(depth.size(), CV_8U);
  const float margin = static_cast<float>(margin_);
  for (int v = 0; v < depth.rows; ++v) {
    const float* d = depth.ptr<float>(v);
    const float* p = prediction_.ptr<float>(v);
    uint8_t* m = mask.ptr<uint8_t>(v);
    // Bitwise & (no branches) so that it vectorises; NaN compares false, so it is never dynamic.
    for (int u = 0, u_end = depth.cols; u < u_end; ++u) {
      m[u] = static_cast<uint8_t>(-static_cast<int>((p[u] > 0.f) & (d[u] > 0.f) & (d[u] < p[u] - margin)));
    }
  }
  if (opening_radius_ > 0) {
    const int size = 2 * opening_radius_ + 1;
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN,
                     cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(size, size)));
  }
  return mask;
}

cv::Mat PredictedDepthEvidence::staticMask(const cv::Mat& depth) {
  if (prediction_.empty() || !(static_margin_ > 0.0)) return cv::Mat();
  cv::Mat mask(depth.size(), CV_8U);
  const float margin = static_cast<float>(static_margin_);
  for (int v = 0; v < depth.rows; ++v) {
    const float* d = depth.ptr<float>(v);
    const float* p = prediction_.ptr<float>(v);
    uint8_t* m = mask.ptr<uint8_t>(v);
    for (int u = 0, u_end = depth.cols; u < u_end; ++u) {
      m[u] = static_cast<uint8_t>(
          -static_cast<int>((p[u] > 0.f) & (d[u] > 0.f) & (std::fabs(d[u] - p[u]) < margin + 0.01f * d[u])));
    }
  }
  return mask;
}

cv::Mat warpDepth(const cv::Mat& depth_src, const CameraIntrinsics& intrinsics,
                  const Eigen::Isometry3d& T_dst_src) {
  cv::Mat out;  // a fresh image: the caller keeps it
  warpWithCompanion(depth_src, cv::Mat(), intrinsics, T_dst_src, cv::Rect(0, 0, depth_src.cols, depth_src.rows), &out,
                    nullptr);
  return out;
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

DualBBoxFilter::DualBBoxFilter(const Options& options) : options_(options) {}

void DualBBoxFilter::reset() {
  previous_depth_.release();
  previous_age_.release();
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
                scaledBoxRect(p.box, o.surround_scale, size), {}, {}};
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

// Algorithm 1, (h_min, h_max) of each box: over the backend mask where it counts a depth (use_mask),
// else over the box with the surround's density taken off.
std::vector<DepthInterval> humanIntervals(const cv::Mat& depth, const std::vector<FilterBox>& boxes,
                                          const Detections& detections, const HistogramOptions& histogram) {
  std::vector<DepthInterval> intervals(boxes.size());
  for (size_t t = 0; t < boxes.size(); ++t) {
    const FilterBox& b = boxes[t];
    if (!b.mask.empty()) {
      // With a mask the histogram is the person's already.
      const cv::Mat& mask = detections.people[b.detection].mask;
      intervals[t] = principalInterval(depth, mask, b.rect, histogram);
      if (intervals[t].valid) continue;
    }
    intervals[t] = principalInterval(depth, cv::Mat(), b.rect, histogram, b.surround);
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

// Geometric addition, the other way: a pixel the box, ring or temporal rule removed is given back
// when the evidence knows it as static (`known`) and neither a person's mask nor dynamic evidence
// covers it.
void keepKnownStatic(cv::Mat known, const std::vector<FilterBox>& boxes, const cv::Mat& dynamic, cv::Mat& state) {
  if (known.empty()) return;
  known.setTo(0, dynamic);
  for (const FilterBox& b : boxes) {
    if (!b.mask.empty()) known(b.mask_area).setTo(0, b.mask);
  }
  state.setTo(kKept, known);
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
cv::Size halfSize(const cv::Size& size) { return cv::Size((size.width + 1) / 2, (size.height + 1) / 2); }

}  // namespace

// Temporal addition: moved cells of neighbouring depth bands, dilated together with one radius.
struct DualBBoxFilter::BandGroup {
  float z_low, z_high;
  int radius;
  cv::Rect cells;   // bounds of the moved cells
  cv::Rect region;  // cells grown by radius, clipped
};

// Temporal addition, at half resolution: last frame's carried pixels are sampled every second
// pixel and row, moved and dilated on a 320x240 grid, and each full-resolution pixel is checked
// against its grid cell (the dilation, 6 px, is coarser than the grid anyway). All images are
// members reused from frame to frame (fresh images cost more in page faults than the work); the
// area-sized steps run on ROIs of them with isolated borders. Fills age_ (frames since a box
// supported each removed pixel); returns the full-resolution pixels the guard looked at.
cv::Rect DualBBoxFilter::guardTemporally(const cv::Mat& depth, const Eigen::Isometry3d& T_cur_prev) {
  const cv::Size size = depth.size(), half = halfSize(size);
  age_.create(size, CV_8U);
  age_.setTo(0);
  if (previous_depth_.empty() || previous_depth_.size() != half) return cv::Rect();
  const cv::Rect bounds = warpWithCompanion(previous_depth_, previous_age_, intrinsics_.scaled(0.5), T_cur_prev,
                                            previous_bounds_, &warped_, &warped_age_);
  if (bounds.empty()) return cv::Rect();
  cv::Rect area;  // half-resolution cells the dilated groups cover
  const std::vector<BandGroup> groups = temporalBandGroups(bounds, half, &area);
  dilateBandGroups(groups, half, area);
  return guardPixels(depth, area);
}

// Temporal addition, the dilation radii: the moved cells (in bounds) grouped by depth band, each
// group with the radius of its nearest cell; *area becomes the union of the groups' regions.
std::vector<DualBBoxFilter::BandGroup> DualBBoxFilter::temporalBandGroups(const cv::Rect& bounds,
                                                                          const cv::Size& half,
                                                                          cv::Rect* area) const {
  // Each moved cell is dilated by how far a person moves in a frame
  // (temporal_person_motion metres) as seen at its depth, and by no less than
  // temporal_dilation pixels: a walking person at 0.7 m crosses ~30 px a frame, at 3 m ~7 px.
  // Cells are grouped in depth bands, each dilated with the radius of its nearest cell, so
  // that a near person does not widen the guard of far ones.
  const Options& o = options_;
  constexpr int kBands = 3;
  const float band_edges[kBands + 1] = {0.f, 1.f, 2.f, std::numeric_limits<float>::infinity()};
  float band_nearest[kBands];
  int band_u0[kBands], band_v0[kBands], band_u1[kBands], band_v1[kBands];
  for (int k = 0; k < kBands; ++k) {
    band_nearest[k] = std::numeric_limits<float>::infinity();
    band_u0[k] = band_v0[k] = std::numeric_limits<int>::max();
    band_u1[k] = band_v1[k] = -1;
  }
  auto bandOf = [&](float z) {
    int k = 0;
    while (k + 1 < kBands && z >= band_edges[k + 1]) ++k;
    return k;
  };
  for (int v = bounds.y; v < bounds.y + bounds.height; ++v) {
    const float* w = warped_.ptr<float>(v);
    for (int u = bounds.x, u_end = bounds.x + bounds.width; u < u_end; ++u) {
      if (!(w[u] > 0.f)) continue;
      const int k = bandOf(w[u]);
      band_nearest[k] = std::min(band_nearest[k], w[u]);
      band_u0[k] = std::min(band_u0[k], u);
      band_u1[k] = std::max(band_u1[k], u);
      band_v0[k] = std::min(band_v0[k], v);
      band_v1[k] = std::max(band_v1[k], v);
    }
  }
  // Neighbouring bands whose radii differ by at most one cell are dilated together with the
  // larger radius (one pass instead of two; typically everyone beyond ~1.3 m).
  std::vector<BandGroup> groups;
  const double half_fx = intrinsics_.scaled(0.5).fx;
  const int min_radius = std::max(0, (o.temporal_dilation + 1) / 2);
  for (int k = 0; k < kBands; ++k) {
    if (band_u1[k] < 0) continue;
    const double motion_px = half_fx * o.temporal_person_motion / band_nearest[k];
    const int radius = std::max(min_radius, std::min(kMaxTemporalRadius, static_cast<int>(std::ceil(motion_px))));
    const cv::Rect cells(band_u0[k], band_v0[k], band_u1[k] - band_u0[k] + 1, band_v1[k] - band_v0[k] + 1);
    if (!groups.empty() && std::abs(groups.back().radius - radius) <= 1) {
      groups.back().z_high = band_edges[k + 1];
      groups.back().radius = std::max(groups.back().radius, radius);
      groups.back().cells |= cells;
    } else {
      groups.push_back({band_edges[k], band_edges[k + 1], radius, cells, cv::Rect()});
    }
  }
  for (BandGroup& g : groups) {
    const int r = g.radius;
    g.region = cv::Rect(g.cells.x - r, g.cells.y - r, g.cells.width + 2 * r, g.cells.height + 2 * r) &
               cv::Rect(0, 0, half.width, half.height);
    *area |= g.region;
  }
  return groups;
}

// Temporal addition, the dilation: nearest and farthest moved depth around each cell of area, and
// the youngest age there, into nearest_inverse_, farthest_ and youngest_.
void DualBBoxFilter::dilateBandGroups(const std::vector<BandGroup>& groups, const cv::Size& half,
                                      const cv::Rect& area) {
  for (cv::Mat* m : {&inverse_, &nearest_inverse_, &farthest_, &band_depth_, &band_nearest_inverse_, &band_farthest_}) {
    m->create(half, CV_32F);
  }
  for (cv::Mat* m : {&age_or_max_, &youngest_, &band_youngest_}) m->create(half, CV_8U);
  const bool one_group = groups.size() == 1;  // dilated straight into the results
  if (!one_group) {
    nearest_inverse_(area).setTo(0);
    farthest_(area).setTo(0);
    youngest_(area).setTo(255);
  }
  const int border = cv::BORDER_CONSTANT | cv::BORDER_ISOLATED;
  const cv::Point anchor(-1, -1);
  for (const BandGroup& g : groups) {
    const cv::Rect& region = g.region;
    const float z_low = g.z_low, z_high = g.z_high;
    // A group of every depth reads the moved depth as it is; others copy their band out.
    const bool all_depths = one_group;
    for (int v = region.y; v < region.y + region.height; ++v) {
      const float* w = warped_.ptr<float>(v);
      const uint8_t* a = warped_age_.ptr<uint8_t>(v);
      float* inv = inverse_.ptr<float>(v);
      uint8_t* am = age_or_max_.ptr<uint8_t>(v);
      if (all_depths) {
        for (int u = region.x, u_end = region.x + region.width; u < u_end; ++u) {
          const bool moved = w[u] > 0.f;
          inv[u] = moved ? 1.f / w[u] : 0.f;
          am[u] = moved ? a[u] : 255;
        }
        continue;
      }
      float* depth_in_band = band_depth_.ptr<float>(v);
      for (int u = region.x, u_end = region.x + region.width; u < u_end; ++u) {
        const bool in_band = w[u] > 0.f && w[u] >= z_low && w[u] < z_high;
        inv[u] = in_band ? 1.f / w[u] : 0.f;
        depth_in_band[u] = in_band ? w[u] : 0.f;
        am[u] = in_band ? a[u] : 255;
      }
    }
    // A square kernel: OpenCV runs it as separable row and column passes (an ellipse is ~10x slower).
    const int r = g.radius;
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * r + 1, 2 * r + 1));
    cv::Mat band_nearest_inverse = (one_group ? nearest_inverse_ : band_nearest_inverse_)(region);
    cv::Mat band_farthest = (one_group ? farthest_ : band_farthest_)(region);
    cv::Mat band_youngest = (one_group ? youngest_ : band_youngest_)(region);
    cv::dilate(inverse_(region), band_nearest_inverse, kernel, anchor, 1, border, cv::Scalar(0));
    cv::dilate((all_depths ? warped_ : band_depth_)(region), band_farthest, kernel, anchor, 1, border, cv::Scalar(0));
    cv::erode(age_or_max_(region), band_youngest, kernel, anchor, 1, border, cv::Scalar(255));
    if (one_group) continue;
    cv::Mat nearest_here = nearest_inverse_(region), farthest_here = farthest_(region),
            youngest_here = youngest_(region);
    cv::max(nearest_here, band_nearest_inverse, nearest_here);
    cv::max(farthest_here, band_farthest, farthest_here);
    cv::min(youngest_here, band_youngest, youngest_here);
  }
}

// Temporal addition, the guard: kept pixels whose depth lies in their cell's guarded range are
// removed (state_ kRemoved, age_ the cell's youngest age + 1). Returns the full-resolution area.
cv::Rect DualBBoxFilter::guardPixels(const cv::Mat& depth, const cv::Rect& area) {
  const Options& o = options_;
  const cv::Size size = depth.size(), half = halfSize(size);
  const cv::Mat nearest_inverse = nearest_inverse_(area), farthest = farthest_(area), youngest = youngest_(area);
  // Per cell, the depth range a pixel must fall in to be guarded: (nearest - margin,
  // farthest + margin), empty where nothing moved near or the youngest pixel is too old.
  const float margin = static_cast<float>(o.temporal_margin);
  for (cv::Mat* m : {&guard_low_, &guard_high_}) m->create(half, CV_32F);
  for (int v = 0; v < area.height; ++v) {
    const float* ni = nearest_inverse.ptr<float>(v);
    const float* fa = farthest.ptr<float>(v);
    const uint8_t* yo = youngest.ptr<uint8_t>(v);
    float* low = guard_low_.ptr<float>(v + area.y) + area.x;
    float* high = guard_high_.ptr<float>(v + area.y) + area.x;
    for (int u = 0, u_end = area.width; u < u_end; ++u) {
      const bool guarded = ni[u] > 0.f && yo[u] < o.temporal_max_age;
      low[u] = guarded ? 1.f / ni[u] - margin : std::numeric_limits<float>::infinity();
      high[u] = fa[u] + margin;
    }
  }
  const cv::Rect full_area = cv::Rect(2 * area.x, 2 * area.y, 2 * area.width, 2 * area.height) &
                             cv::Rect(0, 0, size.width, size.height);
  for (int v = full_area.y; v < full_area.y + full_area.height; ++v) {
    const float* d = depth.ptr<float>(v);
    const float* low = guard_low_.ptr<float>(v / 2);
    const float* high = guard_high_.ptr<float>(v / 2);
    const uint8_t* yo = youngest_.ptr<uint8_t>(v / 2);
    uint8_t* s = state_.ptr<uint8_t>(v);
    uint8_t* ag = age_.ptr<uint8_t>(v);
    // Most pixels are kept and unguarded: the early exits beat a branch-free form here.
    for (int u = full_area.x, u_end = full_area.x + full_area.width; u < u_end; ++u) {
      const int c = u / 2;
      if (s[u] == kKept && d[u] > 0.f && d[u] > low[c] && d[u] < high[c]) {
        s[u] = kRemoved;
        ag[u] = static_cast<uint8_t>(yo[c] + 1);
      }
    }
  }
  return full_area;
}

// Geometric addition: the DynamicEvidence's mask (empty when off). Applied in the output pass; the
// pixels it removes keep their state (kept), so they are not carried to the next frame: they may be
// background.
cv::Mat DualBBoxFilter::geometricEvidence(const cv::Mat& depth) {
  cv::Mat dynamic;
  if (options_.geometric && evidence_) {
    dynamic = evidence_->dynamicMask(depth);
    if (dynamic.size() != depth.size() || dynamic.type() != CV_8U) {
      throw Error("DualBBoxFilter: DynamicEvidence returned a mask that is not CV_8U of the depth's size");
    }
  }
  return dynamic;
}

// Geometric addition, fused with the detector: a candidate region (a person-like mask the detector
// could not call a person) whose measured pixels are dynamic often enough is a person; all of its
// mask joins the dynamic pixels, also the parts the evidence cannot see (where the person stood
// still, or the prediction had no depth). A candidate lying mostly on last frame's confirmed pixels
// (or on a person the detector reported) stays confirmed without fresh evidence for up to
// candidate_memory frames: once part of a person has reached a keyframe, the prediction holds them
// and shows them as static.
void DualBBoxFilter::confirmCandidates(const cv::Mat& depth, const Detections& detections, cv::Mat* dynamic) {
  if (!(options_.candidate_min_dynamic > 0.0)) return;
  if (confirmed_age_.size() != depth.size()) confirmed_age_ = cv::Mat(depth.size(), CV_8U, cv::Scalar(kNotConfirmed));
  // The detector's people count as confirmed too: a person it loses for a few frames (too close,
  // cut by the border) comes back as a candidate on the same pixels.
  cv::Mat next_age(depth.size(), CV_8U, cv::Scalar(kNotConfirmed));
  for (const PersonDetection& person : detections.people) {
    if (person.score > options_.min_confidence && person.mask.size() == depth.size()) next_age.setTo(0, person.mask);
  }
  for (const PersonDetection& candidate : detections.candidates) {
    if (candidate.mask.empty()) continue;
    if (candidate.mask.size() != depth.size() || candidate.mask.type() != CV_8U) {
      throw Error("DualBBoxFilter: a candidate's mask is not CV_8U of the depth's size");
    }
    cv::Rect area;
    const cv::Mat grown = dilatedOnArea(candidate.mask, options_.mask_dilation, &area);
    if (area.empty()) continue;
    const int age = candidateAge(depth(area), candidate.mask(area), (*dynamic)(area), confirmed_age_(area));
    if (age == kNotConfirmed) continue;
    (*dynamic)(area).setTo(255, grown);
    cv::Mat ages(area.size(), CV_8U, cv::Scalar(kNotConfirmed));
    ages.setTo(age, grown);
    cv::Mat target = next_age(area);
    cv::min(target, ages, target);
  }
  confirmed_age_ = next_age;
}

// 0 with fresh evidence, 1 + the youngest age under it when carried, else kNotConfirmed.
int DualBBoxFilter::candidateAge(const cv::Mat& depth, const cv::Mat& mask, const cv::Mat& dynamic,
                                 const cv::Mat& previous_age) const {
  const cv::Mat inside = mask > 0;
  const cv::Mat measured = inside & (depth > 0.f);
  const int total = cv::countNonZero(measured);
  if (total > 0 && cv::countNonZero(measured & (dynamic > 0)) >= options_.candidate_min_dynamic * total) return 0;
  const cv::Mat carried = inside & (previous_age < kNotConfirmed);
  if (cv::countNonZero(carried) * 2 < cv::countNonZero(inside)) return kNotConfirmed;
  double youngest = kNotConfirmed;
  cv::minMaxLoc(previous_age, &youngest, nullptr, nullptr, nullptr, carried);
  return youngest + 1 <= options_.candidate_memory ? static_cast<int>(youngest) + 1 : kNotConfirmed;
}

// Temporal addition, the carry-over: this frame's people's and guarded pixels, at half resolution,
// into previous_depth_, previous_age_ and previous_bounds_ for the next frame.
void DualBBoxFilter::carryToNextFrame(const cv::Mat& depth, const std::vector<cv::Rect>& areas,
                                      const cv::Rect& guarded_area) {
  // Only people's pixels and pixels guarded for them carry over: ring outliers and geometric
  // removals may be background, and carrying those would let the guard spread over it. They
  // lie in the people's areas and the guarded area; every second pixel and row is kept.
  const cv::Size half = halfSize(depth.size());
  cv::Rect carried;
  for (const cv::Rect& a : areas) carried |= a;
  carried |= guarded_area;
  previous_depth_.create(half, CV_32F);
  previous_depth_.setTo(0);
  previous_age_.create(half, CV_8U);
  int u_min = half.width, v_min = half.height, u_max = -1, v_max = -1;
  for (int v = carried.y + carried.y % 2; v < carried.y + carried.height; v += 2) {
    const float* d = depth.ptr<float>(v);
    const uint8_t* s = state_.ptr<uint8_t>(v);
    const uint8_t* a = age_.ptr<uint8_t>(v);
    float* p = previous_depth_.ptr<float>(v / 2);
    uint8_t* pa = previous_age_.ptr<uint8_t>(v / 2);
    for (int u = carried.x + carried.x % 2, u_end = carried.x + carried.width; u < u_end; u += 2) {
      if ((s[u] == kKept || s[u] == kRemoved) && a[u] == 0) continue;
      p[u / 2] = d[u];
      pa[u / 2] = a[u];  // zero (box-supported) except for temporally guarded pixels
      u_min = std::min(u_min, u / 2);
      u_max = std::max(u_max, u / 2);
      v_min = std::min(v_min, v / 2);
      v_max = std::max(v_max, v / 2);
    }
  }
  previous_bounds_ = u_max < 0 ? cv::Rect() : cv::Rect(u_min, v_min, u_max - u_min + 1, v_max - v_min + 1);
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
  const std::vector<DepthInterval> intervals = humanIntervals(depth, boxes, detections, o.human_histogram);
  const float human_margin = static_cast<float>(o.human_margin);
  std::vector<DepthInterval> second_intervals(boxes.size());
  if (o.separate_occlusions) {
    findOccludedIntervals(depth, boxes, o.human_histogram, human_margin, intervals, &second_intervals);
  }
  const std::vector<cv::Rect> areas = labelPeople(depth, boxes, intervals, second_intervals, human_margin, state_);
  removeRingOutliers(depth, boxes, result.background, o.background_margin, outside_, state_);
  const cv::Rect guarded_area = o.temporal ? guardTemporally(depth, T_cur_prev) : cv::Rect();
  cv::Mat dynamic = geometricEvidence(depth);
  if (!dynamic.empty()) confirmCandidates(depth, detections, &dynamic);
  if (!dynamic.empty() && o.keep_static) keepKnownStatic(evidence_->staticMask(depth), boxes, dynamic, state_);
  writeStaticDepth(depth, state_, dynamic, &result);
  collectPeople(depth, state_, boxes, intervals, areas, &result.people);
  if (o.temporal) carryToNextFrame(depth, areas, guarded_area);
  return result;
}

}  // namespace pf2
