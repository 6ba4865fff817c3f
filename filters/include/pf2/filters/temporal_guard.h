#pragma once
// The Dual-BBox filter's temporal addition: last frame's person pixels (and those it guarded),
// moved into this frame with the camera motion and dilated by how far a person moves in a frame,
// guard this frame's pixels whose depth agrees with them, so people the detector missed for a
// frame, or parts a box cut off, are still removed. A pixel is guarded at most max_age frames
// without a box supporting it. The work runs at half resolution (docs/filters.md).
//
// It works on the filter's per-pixel state image: CV_8U, kKept, kRemoved (removed, not a
// person's), or a person's label (1..254). NOT thread safe (keeps the previous frame).
#include <cstdint>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"

namespace pf2 {

class TemporalGuard {
 public:
  struct Options {
    double person_motion = 0.02;  // metres: the moved previous pixels are dilated by this distance
                                  // as seen at their depth (more pixels for near people); 0.04
                                  // removed 0.5 points more of the people and 12-19 points more of
                                  // the background (docs/filters.md)
    int dilation = 6;             // ... and by at least this many pixels
    double margin = 0.15;         // metres a depth may differ from the moved ones
    int max_age = 4;              // frames a pixel may be guarded without any box supporting it
    // metres, plus 1 % of the depth: a guarded pixel whose surface the previous frame saw this
    // close to where this frame sees it, and gave to the map (or the guard held max_age frames
    // in a row), is spared: nothing moved there. The tracker still leaves it out (a missed
    // person's flat side moves along itself); the map gets it. Without it the guard holds the
    // chair and wall beside a person as long as their mask stays next to them (docs/filters.md).
    // 0 = off.
    double static_tolerance = 0.05;
  };
  static constexpr uint8_t kKept = 0;
  static constexpr uint8_t kRemoved = 255;

  TemporalGuard() : TemporalGuard(Options()) {}
  explicit TemporalGuard(const Options& options) : options_(options) {}

  // Marks kept pixels of `state` that last frame's carried pixels, moved by T_cur_prev (previous
  // camera to this one), guard as kRemoved, those of them whose surface was there before in
  // spared(), and records in age() how many frames each has been
  // guarded without a box. Returns the full-resolution area it looked at (empty on the first
  // frame). depth: CV_32F metres, of the intrinsics' size.
  cv::Rect guard(const cv::Mat& depth, const CameraIntrinsics& intrinsics, const Eigen::Isometry3d& T_cur_prev,
                 cv::Mat& state);
  // Carries this frame's people's pixels (labels in `state`, within `areas`) and the pixels guard()
  // marked (within guarded_area) to the next frame.
  void carry(const cv::Mat& depth, const cv::Mat& state, const std::vector<cv::Rect>& areas,
             const cv::Rect& guarded_area);
  // Forgets the previous frame (new sequence).
  void reset();

  // Per pixel, frames guarded without a box (0: not guarded, or supported by a box). After guard().
  const cv::Mat& age() const { return age_; }
  // Guarded pixels whose surface the previous frame gave to the map, or which the guard has held
  // max_age frames in a row (CV_8U, 255; Options::static_tolerance). After guard().
  const cv::Mat& spared() const { return spared_; }
  const Options& options() const { return options_; }
  void setOptions(const Options& options) { options_ = options; }

 private:
  struct BandGroup;  // moved cells of neighbouring depth bands, dilated together (.cpp)
  std::vector<BandGroup> bandGroups(const cv::Rect& bounds, const cv::Size& half, cv::Rect* area) const;
  void dilateBandGroups(const std::vector<BandGroup>& groups, const cv::Size& half, const cv::Rect& area);
  cv::Rect guardPixels(const cv::Mat& depth, const cv::Rect& area, const Eigen::Isometry3d& T_prev_cur, cv::Mat& state);
  void carrySurfaces(const cv::Mat& depth, const cv::Mat& state);
  int framesHeld(int u, int v, float z, const Eigen::Isometry3d& T_prev_cur) const;

  Options options_;
  CameraIntrinsics intrinsics_;
  // Working images kept between calls (fresh images cost more in page faults than the work).
  cv::Mat age_, warped_, warped_age_, inverse_, nearest_inverse_, farthest_, age_or_max_, youngest_;
  cv::Mat band_depth_, band_nearest_inverse_, band_farthest_, band_youngest_;  // one depth band
  cv::Mat guard_low_, guard_high_;  // depth range guarded per half-resolution cell
  // Last frame's carried pixels at half resolution (every second pixel and row):
  cv::Mat previous_depth_;    // CV_32F depth of the people's and guarded pixels, 0 elsewhere
  cv::Mat previous_age_;      // CV_8U frames since a box last supported each (where depth > 0)
  cv::Rect previous_bounds_;  // bounds of previous_depth_'s non-zero pixels: the warp scans only these
  cv::Mat held_;              // CV_8U per pixel, frames in a row guard() has held its surface
  cv::Mat spared_;            // CV_8U per pixel, 255: guarded, but its surface was there before
  cv::Mat previous_surface_;  // CV_32F depth of the pixels the previous frame gave to the map or held
  cv::Mat previous_held_;     // CV_8U held_ of those pixels (0: given to the map)
};

}  // namespace pf2
