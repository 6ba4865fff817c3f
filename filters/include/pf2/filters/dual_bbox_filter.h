#pragma once
// Dual-BBox filter: Algorithm 1 of the paper (§III-A) plus three optional additions. It splits a
// depth image into the static depth D_b (people removed; the tracker and the map use it) and one
// depth image D_h^t per detected person (the human tracker and the body fitter use those).
//
// The paper's rule, per pixel, made independent of the order of the boxes:
//   - inside person box t with depth in (h_min^t - human_margin, h_max^t + human_margin): person t,
//     removed from D_b (Algorithm 1, scene separation);
//   - inside some box but consistent with no box's person: given back to D_b (lines 12-14);
//   - in the ring between a box and the box enlarged by lambda, depth outside
//     (b_min - background_margin, b_max + background_margin): removed (lines 10-11);
//   - everything else: kept.
// (h_min, h_max) and (b_min, b_max) are principal intervals of depth histograms; see
// principalInterval() for their exact definition.
//
// Additions (each off by default, see Options):
//   use_mask  — where a backend gives a person mask, the mask dilated by mask_dilation pixels is
//               removed too and the person's histogram is taken over the mask only;
//   temporal  — the previous frame's person pixels (and those it guarded), moved into this frame
//               with the camera motion and dilated, guard pixels whose depth agrees with them
//               (boxes that were missed or too small); a pixel is guarded at most temporal_max_age
//               frames without a box supporting it;
//   geometric — (class GeometricAddition) a DynamicEvidence hook (depth in front of a static-map
//               prediction) marks pixels dynamic wherever it has an opinion; a detector's
//               candidate region with enough of that evidence is removed whole
//               (candidate_min_dynamic). With keep_static, depth the evidence knows as static is
//               given back where only the box, ring or temporal rule took it, except on a mask and
//               on the skeleton of a person posed without one; with keep_static_behind_masks also
//               on a mask where it lies behind the person or in the ring the mask's dilation
//               added. An evidence given with geometric off still confirms the candidates the
//               detector is sure of or that follow confirmed pixels, and its static opinion still
//               counts (a caller without the prediction gives only a floor plane).
//   outside_masks_tracker_only — what the box, ring and temporal rules took outside the masks is
//               kept for the map and reported for the tracker to leave out.
#include <memory>
#include <optional>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/core/camera_intrinsics.h"
#include "pf2/detection/human_detector.h"
#include "pf2/filters/geometric_addition.h"
#include "pf2/filters/person_depth_gate.h"
#include "pf2/filters/temporal_guard.h"

namespace pf2 {

// Principal interval of a depth histogram (metres); valid is false when no depth was counted.
struct DepthInterval {
  double min = 0, max = 0;
  bool valid = false;
  bool contains(double depth, double margin) const {
    return valid && depth > min - margin && depth < max + margin;
  }
};

struct HistogramOptions {
  double bin_width = 0.05;      // histogram bin, metres
  double max_depth = 10.0;      // depths at or beyond this are not counted, metres
  double window = 1.0;          // width of the depth window searched for the most pixels, metres:
                                // a walking person seen by a camera pitched down spans ~1 m in z
                                // (1.8 m x sin 30 deg plus the body's thickness; see docs/filters.md)
  double grow_fraction = 0.03;  // the window grows by each neighbouring bin holding at least this
                                // fraction of the window's mean bin count (a person's depth tail)
  double near_preference = 0.6; // the nearest window holding at least this fraction of the best
                                // window's count wins (1 = plain maximum): a person occludes what
                                // is behind them, so their mode is the nearest large one
  int stride = 1;               // every stride-th pixel of every stride-th row is counted (speed)
  double surround_weight = 0.0; // with a surround given: what is as dense around the box as in it
                                // is background, so the surround's counts, scaled to the box's
                                // area and by this weight, are taken off the box's (0 = plain counts)
};

// Histogram of the valid depths (finite, > 0, < max_depth) of `depth` where `mask` is non-zero (an
// empty mask counts all pixels) inside `roi`. With a non-empty `surround` (a rectangle around roi,
// e.g. the box enlarged by lambda) and options.surround_weight > 0, each bin loses
// surround_weight x (roi's area / the area of surround minus roi) x the bin's count over the pixels
// of surround outside roi, floored at 0: a person is what is dense in the box and not around it,
// which keeps a wall that fills most of a wide box, or a nearer person whose box contains this
// one, from winning. The principal interval is the window of options.window metres (a whole number
// of bins) holding the most depths; among windows holding at least near_preference of that count
// the nearest is taken; it is then grown bin by bin on either side while the neighbouring bin holds
// >= grow_fraction x the window's mean bin count. The interval spans the outer edges of the chosen
// bins. Thread safe.
DepthInterval principalInterval(const cv::Mat& depth, const cv::Mat& mask, const cv::Rect& roi,
                                const HistogramOptions& options, const cv::Rect& surround = cv::Rect());

// The simplest evidence: a predicted static depth image for the current view (rendered from a map,
// or the last static depth moved into this view). Pixels measured more than `margin` metres in
// front of a known prediction are dynamic. With opening_radius > 0 the mask is opened (eroded,
// then dilated) by a disc of that many pixels: a moving person is a large blob, while a prediction
// a little off (a pose guess, lens distortion) marks thin bands along depth edges that are static.
// NOT thread safe.
class PredictedDepthEvidence : public DynamicEvidence {
 public:
  explicit PredictedDepthEvidence(double margin = 0.15, int opening_radius = 0)
      : margin_(margin), opening_radius_(opening_radius) {}
  // CV_32F metres, 0 = no prediction; must have the size of the depth images filtered next.
  void setPrediction(const cv::Mat& predicted_depth) { prediction_ = predicted_depth; }
  cv::Mat dynamicMask(const cv::Mat& depth) override;
  // Measured within static_margin (metres, plus 1 % of the depth) of a known prediction, or within
  // plane_margin of the static plane.
  cv::Mat staticMask(const cv::Mat& depth) override;
  void setStaticMargin(double metres) { static_margin_ = metres; }
  // A plane of this view known to be static (the floor: people stand on it, they are not part of
  // it), in the camera frame, metres; std::nullopt for none. Depth whose point lies within
  // plane_margin of it (plus 1 % of the depth) is static too, also where the prediction has no
  // depth: the floor beside a person no keyframe has seen without them. `intrinsics` are those of
  // the depth images filtered next.
  void setStaticPlane(const std::optional<Eigen::Hyperplane<double, 3>>& plane_c, const CameraIntrinsics& intrinsics) {
    plane_c_ = plane_c;
    plane_intrinsics_ = intrinsics;
  }
  void setPlaneMargin(double metres) { plane_margin_ = metres; }

 private:
  double static_margin_ = 0.0;  // 0 = no static evidence from the prediction
  double plane_margin_ = 0.0;   // 0 = no static evidence from the plane
  std::optional<Eigen::Hyperplane<double, 3>> plane_c_;
  CameraIntrinsics plane_intrinsics_;
  double margin_;
  int opening_radius_;
  cv::Mat prediction_;
};

// Moves a depth image into another view: each pixel with depth is back-projected, transformed by
// T_dst_src and projected (z-buffered, nearest wins). CV_32F in and out, 0 = none. Thread safe.
cv::Mat warpDepth(const cv::Mat& depth_src, const CameraIntrinsics& intrinsics,
                  const Eigen::Isometry3d& T_dst_src);

class DualBBoxFilter {
 public:
  struct Options {
    // --- the paper (Algorithm 1) ---
    double min_confidence = 0.5;     // boxes with score > this are used
    double box_scale = 1.2;          // lambda: boxes enlarged about their centre for the ring
    double background_margin = 0.1;  // metres around (b_min, b_max)
    double human_margin = 0.2;       // metres around (h_min, h_max)
    double surround_scale = 2.0;     // box enlarged by this about its centre is the surround whose
                                     // depths human_histogram.surround_weight takes off the box's
    bool separate_occlusions = true; // overlapping boxes that found the same person: the box where
                                     // that person is less dense looks again (see the .cpp)
    HistogramOptions human_histogram{0.05, 10.0, 1.0, 0.03, 0.6, 1, 0.5};  // for each box's D_h^t:
                                     // HistogramOptions' defaults, with half the surround's
                                     // density taken off (0.5: measured, docs/filters.md)
    HistogramOptions background_histogram{0.05, 10.0, 0.4, 0.25, 1.0, 2};  // for D_b: the most
                                     // populated 0.4 m (plain maximum), grown by bins >= 25 %,
                                     // counted on every second pixel and row
    // --- beyond the paper ---
    bool use_mask = false;           // use backend masks where present
    int mask_dilation = 3;           // pixels the mask is dilated by
    int mask_box_reach = 0;          // with a mask: the box and ring rules remove depth only within
                                     // this many pixels of it (the floor at a person's feet and the
                                     // wall beside them lie in the box at the person's depth);
                                     // 0 = everywhere in the box and ring (the paper)
    int joint_min_count = 3;         // with a mask: when the median depth under at least this many
                                     // confident keypoints lies outside the mask's interval, the
                                     // interval is taken again near it (see the .cpp; 0 = off)
    double joint_min_score = 0.3;    // confident keypoint: score at least this
    PersonDepthGate::Options depth_gate;  // with masks: removed depth apart from the person's depth
                                     // around it is given back (PersonDepthGate; radius 0 = off)
    bool temporal = false;           // guard with last frame's person pixels (TemporalGuard)
    TemporalGuard::Options temporal_guard;
    bool geometric = false;          // remove what the DynamicEvidence given with
                                     // setDynamicEvidence() marks dynamic
    GeometricAddition::Options geometric_addition;  // candidates and static evidence (any evidence)
    // With keep_static: depth under a person's dilated mask that the evidence knows as static and
    // that lies more than human_margin behind the person's interval (the wall the segmenter's
    // blurred edge, or a real person's hair, spills over) or in the ring mask_dilation added
    // around the segmenter's own mask is kept in D_b too, and reported in
    // Result::kept_for_map_only for callers whose colour term should leave it out.
    bool keep_static_behind_masks = false;
    // What the box, ring and temporal rules removed outside every person's dilated mask, unless
    // it is the box of a person without a mask or the dynamic evidence marks it, is kept in D_b
    // for the map and reported in Result::kept_for_map_only, so a caller's tracker still leaves
    // it out. Meant for masks that follow people's outlines closely (video matting and crop
    // masks), where what those rules take beside a mask is mostly background.
    bool outside_masks_tracker_only = false;
  };

  struct Person {
    int detection = -1;   // index into the Detections' people
    PersonBox box;        // the detector's box, clipped to the image
    DepthInterval interval;  // (h_min, h_max) without margin
    cv::Rect area;        // image pixels the two images below cover (box, and mask with use_mask)
    cv::Mat depth;        // D_h^t on area: CV_32F of area's size, this person's depth, 0 elsewhere
    cv::Mat mask;         // CV_8U of area's size, 255 where depth > 0
    // Both images at image size (a copy; for callers that want whole images).
    cv::Mat fullDepth(const cv::Size& image) const;
    cv::Mat fullMask(const cv::Size& image) const;
  };

  struct Result {
    cv::Mat static_depth;      // D_b, CV_32F metres, 0 where removed or no measurement
    cv::Mat removed;           // CV_8U, 255 where a measured depth was removed from D_b
    // CV_8U, 255 where D_b keeps depth under a person's mask (Options::keep_static_behind_masks)
    // or that the box, ring or temporal rule took outside the masks
    // (Options::outside_masks_tracker_only): right as depth for the map, but still doubtful for
    // a tracker (a person's colour, or a person's carried outline); empty when none.
    cv::Mat kept_for_map_only;
    std::vector<Person> people;
    DepthInterval background;  // (b_min, b_max)
  };

  DualBBoxFilter() : DualBBoxFilter(Options()) {}
  explicit DualBBoxFilter(const Options& options);

  // Needed by the temporal addition (to move last frame's pixels), of the depth images' size:
  // filter() throws without it when the temporal addition is on (no silent default camera).
  void setIntrinsics(const CameraIntrinsics& intrinsics) { intrinsics_ = intrinsics; }
  // Needed by the geometric addition; nullptr switches it off.
  void setDynamicEvidence(std::shared_ptr<DynamicEvidence> evidence) { geometric_.setEvidence(std::move(evidence)); }

  // Filters one depth image (CV_32F metres; NaN, inf and negatives count as no measurement).
  // T_cur_prev moves points of the previous filtered frame into this one (identity for a still
  // camera); only the temporal addition reads it. Throws pf2::Error on a depth of another type.
  // NOT thread safe (keeps the previous frame for the temporal addition).
  Result filter(const cv::Mat& depth, const Detections& detections,
                const Eigen::Isometry3d& T_cur_prev = Eigen::Isometry3d::Identity());

  // Forgets the previous frame (new sequence). NOT thread safe.
  void reset();

  const Options& options() const { return options_; }
  // Replaces the options; the temporal state is kept. NOT thread safe.
  void setOptions(const Options& options) {
    options_ = options;
    temporal_.setOptions(options.temporal_guard);
    depth_gate_.setOptions(options.depth_gate);
    geometric_.setOptions(options.geometric_addition);
  }

 private:

  const CameraIntrinsics& temporalIntrinsics(const cv::Mat& depth) const;

  Options options_;
  std::optional<CameraIntrinsics> intrinsics_;
  // Working images kept between calls: allocating them anew costs more than filling them.
  cv::Mat depth_, state_, outside_;
  TemporalGuard temporal_;
  PersonDepthGate depth_gate_;
  GeometricAddition geometric_;
};

// Integer pixel rectangle of a box scaled by `scale` about its centre, clipped to the image.
cv::Rect scaledBoxRect(const PersonBox& box, double scale, const cv::Size& image);

}  // namespace pf2
