#pragma once
// The Dual-BBox filter's local depth gate: depth that a box, ring or temporal rule removed next to
// a person is given back when it lies clearly in front of or behind every depth of that person
// around it. The box rule takes a whole depth interval (a metre or more: a body is deep in z), so
// the wall a few decimetres behind a person's shoulder, or a table in front of their legs, falls
// in it; locally the person spans only centimetres. Depth continuous with the person (the floor at
// their feet) stays removed.
//
// The person's depth comes from the detector's masks ("core": mask pixels whose depth lies in the
// person's interval), so the gate acts only where a mask exists. NOT thread safe (keeps working
// images between calls).
#include <opencv2/core.hpp>

namespace pf2 {

class PersonDepthGate {
 public:
  struct Options {
    int radius = 0;        // pixels: a removed pixel is compared with the core depths within this
                           // square window (taken at half resolution, so within a pixel or two);
                           // 0 = gate off, [0, 100]
    double margin = 0.3;   // metres beyond the window's nearest / farthest core depth, [0, 2]
  };

  PersonDepthGate() = default;
  explicit PersonDepthGate(const Options& options) : options_(options) {}

  // depth: CV_32F metres (0 = none); core: CV_8U, non-zero where depth is surely a person's.
  // Returns CV_8U of depth's size, 255 where a measured depth has core depths within `radius`
  // and lies more than `margin` in front of the nearest or behind the farthest of them; empty when
  // the gate is off or the core is empty.
  cv::Mat outsidePeople(const cv::Mat& depth, const cv::Mat& core);

  const Options& options() const { return options_; }
  void setOptions(const Options& options) { options_ = options; }

 private:
  void blockExtremes(const cv::Mat& depth, const cv::Mat& core);

  Options options_;
  cv::Mat nearest_, farthest_;  // core depths' minimum / maximum at half resolution (working images)
};

}  // namespace pf2
