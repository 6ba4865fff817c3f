#include "pf2/filters/temporal_guard.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

#include "image_ops.h"

namespace pf2 {
namespace {

constexpr uint8_t kKept = TemporalGuard::kKept;
constexpr uint8_t kRemoved = TemporalGuard::kRemoved;
constexpr int kMaxTemporalRadius = 40;  // half-resolution cells: 80 px, a person at 0.25 m
// Half-resolution cells around where a pixel's surface lands in the previous frame that are looked
// at for it: the rounding to the grid and the pose's error move it by about a cell, and next to a
// person's outline that cell may be the person's (on pf2_synth without the residual mask, 1 cell
// rather than 0 kept 0.2-0.4 points more of the static depth).
constexpr int kSurfaceSearch = 1;

}  // namespace

void TemporalGuard::reset() {
  previous_depth_.release();
  previous_age_.release();
  previous_surface_.release();
  previous_held_.release();
}

// Temporal addition: moved cells of neighbouring depth bands, dilated together with one radius.
struct TemporalGuard::BandGroup {
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
cv::Rect TemporalGuard::guard(const cv::Mat& depth, const CameraIntrinsics& intrinsics,
                              const Eigen::Isometry3d& T_cur_prev, cv::Mat& state) {
  intrinsics_ = intrinsics;
  const cv::Size size = depth.size(), half = halfSize(size);
  age_.create(size, CV_8U);
  age_.setTo(0);
  for (cv::Mat* m : {&held_, &spared_}) {
    m->create(size, CV_8U);
    m->setTo(0);
  }
  if (previous_depth_.empty() || previous_depth_.size() != half) return cv::Rect();
  const cv::Rect bounds = warpWithCompanion(previous_depth_, previous_age_, intrinsics_.scaled(0.5), T_cur_prev,
                                            previous_bounds_, &warped_, &warped_age_);
  if (bounds.empty()) return cv::Rect();
  cv::Rect area;  // half-resolution cells the dilated groups cover
  const std::vector<BandGroup> groups = bandGroups(bounds, half, &area);
  dilateBandGroups(groups, half, area);
  return guardPixels(depth, area, T_cur_prev.inverse(), state);
}

// Temporal addition, the dilation radii: the moved cells (in bounds) grouped by depth band, each
// group with the radius of its nearest cell; *area becomes the union of the groups' regions.
std::vector<TemporalGuard::BandGroup> TemporalGuard::bandGroups(const cv::Rect& bounds, const cv::Size& half,
                                                                cv::Rect* area) const {
  // Each moved cell is dilated by how far a person moves in a frame
  // (person_motion metres) as seen at its depth, and by no less than
  // dilation pixels: a walking person at 0.7 m crosses ~30 px a frame, at 3 m ~7 px.
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
  const int min_radius = std::max(0, (o.dilation + 1) / 2);
  for (int k = 0; k < kBands; ++k) {
    if (band_u1[k] < 0) continue;
    const double motion_px = half_fx * o.person_motion / band_nearest[k];
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
void TemporalGuard::dilateBandGroups(const std::vector<BandGroup>& groups, const cv::Size& half,
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

// How many frames in a row the guard has held, for the map, the surface pixel (u, v) sees at
// depth z, as the previous frame saw it: moved into the previous camera (T_prev_cur), looked for
// within kSurfaceSearch cells of where it lands on the half-resolution grid, compared within
// static_tolerance. 0: the previous frame gave that surface to the map; -1: it saw another surface
// there (something moved), a person's, or nothing.
int TemporalGuard::framesHeld(int u, int v, float z, const Eigen::Isometry3d& T_prev_cur) const {
  if (options_.static_tolerance <= 0.0 || previous_surface_.empty()) return -1;
  const Eigen::Vector3d p_prev = T_prev_cur * intrinsics_.backProject(u, v, z);
  if (!(p_prev.z() > 0.0)) return -1;
  const Eigen::Vector2d q = intrinsics_.project(p_prev);
  const double col = std::round(0.5 * q.x()), row = std::round(0.5 * q.y());
  const cv::Rect cells = cv::Rect(static_cast<int>(std::clamp(col, -1e6, 1e6)) - kSurfaceSearch,
                                  static_cast<int>(std::clamp(row, -1e6, 1e6)) - kSurfaceSearch,
                                  2 * kSurfaceSearch + 1, 2 * kSurfaceSearch + 1) &
                         cv::Rect(0, 0, previous_surface_.cols, previous_surface_.rows);
  const float z_prev = static_cast<float>(p_prev.z());
  const float tolerance = static_cast<float>(options_.static_tolerance + 0.01 * p_prev.z());
  int held = -1;
  for (int r = cells.y; r < cells.y + cells.height; ++r) {
    const float* seen = previous_surface_.ptr<float>(r);
    const uint8_t* seen_held = previous_held_.ptr<uint8_t>(r);
    for (int c = cells.x; c < cells.x + cells.width; ++c) {
      if (!(seen[c] > 0.f) || std::abs(seen[c] - z_prev) >= tolerance) continue;
      held = held < 0 ? seen_held[c] : std::min<int>(held, seen_held[c]);
    }
  }
  return held;
}

// Temporal addition, the guard: kept pixels whose depth lies in their cell's guarded range are
// removed (state kRemoved, age_ the cell's youngest age + 1). Those whose surface the previous
// frame gave to the map, or the guard has held from it max_age frames in a row, are marked in
// spared_ (nothing moved there: the chair or wall beside a person, or a missed person standing
// still); the others count in held_ the frames in a row they are held. Returns the
// full-resolution area.
cv::Rect TemporalGuard::guardPixels(const cv::Mat& depth, const cv::Rect& area, const Eigen::Isometry3d& T_prev_cur,
                                    cv::Mat& state) {
  const Options& o = options_;
  const cv::Size size = depth.size(), half = halfSize(size);
  const cv::Mat nearest_inverse = nearest_inverse_(area), farthest = farthest_(area), youngest = youngest_(area);
  // Per cell, the depth range a pixel must fall in to be guarded: (nearest - margin,
  // farthest + margin), empty where nothing moved near or the youngest pixel is too old.
  const float margin = static_cast<float>(o.margin);
  for (cv::Mat* m : {&guard_low_, &guard_high_}) m->create(half, CV_32F);
  for (int v = 0; v < area.height; ++v) {
    const float* ni = nearest_inverse.ptr<float>(v);
    const float* fa = farthest.ptr<float>(v);
    const uint8_t* yo = youngest.ptr<uint8_t>(v);
    float* low = guard_low_.ptr<float>(v + area.y) + area.x;
    float* high = guard_high_.ptr<float>(v + area.y) + area.x;
    for (int u = 0, u_end = area.width; u < u_end; ++u) {
      const bool guarded = ni[u] > 0.f && yo[u] < o.max_age;
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
    uint8_t* s = state.ptr<uint8_t>(v);
    uint8_t* ag = age_.ptr<uint8_t>(v);
    uint8_t* hl = held_.ptr<uint8_t>(v);
    uint8_t* sp = spared_.ptr<uint8_t>(v);
    // Most pixels are kept and unguarded: the early exits beat a branch-free form here.
    for (int u = full_area.x, u_end = full_area.x + full_area.width; u < u_end; ++u) {
      const int c = u / 2;
      if (s[u] != kKept || !(d[u] > 0.f) || d[u] <= low[c] || d[u] >= high[c]) continue;
      s[u] = kRemoved;
      ag[u] = static_cast<uint8_t>(yo[c] + 1);
      const int held = framesHeld(u, v, d[u], T_prev_cur);
      if (held == 0 || held >= o.max_age) {
        sp[u] = 255;
      } else {
        hl[u] = static_cast<uint8_t>(std::max(held, 0) + 1);
      }
    }
  }
  return full_area;
}

// Temporal addition, the carry-over: this frame's people's and guarded pixels, at half resolution,
// into previous_depth_, previous_age_ and previous_bounds_ for the next frame.
void TemporalGuard::carry(const cv::Mat& depth, const cv::Mat& state, const std::vector<cv::Rect>& areas,
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
    const uint8_t* s = state.ptr<uint8_t>(v);
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
  carrySurfaces(depth, state);
}

// Temporal addition, the carry-over of the surfaces this frame gave to the map (kept or spared)
// or the guard held (every second pixel and row) into previous_surface_ and previous_held_.
void TemporalGuard::carrySurfaces(const cv::Mat& depth, const cv::Mat& state) {
  if (options_.static_tolerance <= 0.0) {
    previous_surface_.release();
    return;
  }
  const cv::Size half = halfSize(depth.size());
  previous_surface_.create(half, CV_32F);
  previous_held_.create(half, CV_8U);
  for (int v = 0; v < half.height; ++v) {
    const float* d = depth.ptr<float>(2 * v);
    const uint8_t* s = state.ptr<uint8_t>(2 * v);
    const uint8_t* h = held_.ptr<uint8_t>(2 * v);
    const uint8_t* sp = spared_.ptr<uint8_t>(2 * v);
    float* surface = previous_surface_.ptr<float>(v);
    uint8_t* held = previous_held_.ptr<uint8_t>(v);
    for (int u = 0; u < half.width; ++u) {
      const bool to_map = s[2 * u] == kKept || sp[2 * u], guarded = s[2 * u] == kRemoved && h[2 * u] > 0;
      surface[u] = to_map || guarded ? d[2 * u] : 0.f;
      held[u] = to_map ? 0 : h[2 * u];
    }
  }
}

}  // namespace pf2
