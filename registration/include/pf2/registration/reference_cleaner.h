#pragma once
// Takes out of a reference (keyframe) the points that have moved away since it was taken: a point
// of the reference that a later, aligned frame sees *through* (the later frame measures a surface
// well behind where the point was, along the later camera's ray) is no longer there. A person the
// detector missed when the keyframe was made is taken out this way as soon as they walk off,
// instead of dragging every later frame's alignment after them. (The other half of the free-space
// test, depth measured in front of the reference, is the filter's geometric addition.)
//
// Depth edges are where a slightly wrong pose makes a static foreground point look "seen
// through": the later frame's depth is taken as the smallest of each 3x3 neighbourhood, and a
// point must be seen through by `votes` frames before it is removed.
#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/registration/odometry_frame.h"

namespace pf2 {

class ReferenceCleaner {
 public:
  struct Options {
    bool enabled = true;
    double margin = 0.10;           // metres a later surface must lie behind the point, plus ...
    double relative_margin = 0.03;  // ... this fraction of the point's depth (noise grows with z)
    int votes = 2;                  // frames that must see through a point before it goes, >= 1
    int stride = 2;                 // every stride-th reference pixel and row is tested, >= 1
  };

  ReferenceCleaner() : ReferenceCleaner(Options()) {}
  // Throws pf2::Error when an option is out of range.
  explicit ReferenceCleaner(const Options& options);

  // A new reference: forgets the votes. NOT thread safe (this and update()).
  void reset();
  // Votes with `current`, aligned to the reference at T_ref_cur, and removes the points with
  // enough votes from every pyramid level of the reference's depth (a stride x stride block at
  // full resolution). Returns the number of reference pixels removed by this call.
  int update(OdometryFrame* reference, const OdometryFrame& current, const Eigen::Isometry3d& T_ref_cur);

  const Options& options() const { return options_; }

 private:
  Options options_;
  cv::Mat votes_;        // CV_8U, per tested reference pixel (reference size / stride)
  cv::Mat filled_cur_;   // CV_32F, current depth with holes set to the largest float, reused
  cv::Mat nearest_cur_;  // CV_32F, current depth's 3x3 minimum (holes excluded), reused
};

}  // namespace pf2
