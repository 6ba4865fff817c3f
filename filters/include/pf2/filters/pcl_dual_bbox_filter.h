#pragma once
// The Dual-BBox filter the PCL way (pcl::Filter<PointT>: setInputCloud, filter(output)), for
// organized clouds from an RGB-D camera. It runs exactly the image path (DualBBoxFilter) on the
// cloud's z values, so both give the same result. This header includes PCL on purpose (it is the
// PCL-facing adapter); the pipeline uses dual_bbox_filter.h, which does not.
//
//   pf2::PclDualBBoxFilter<pcl::PointXYZRGB> f;
//   f.setInputCloud(cloud);            // organized, width x height = the colour image
//   f.setDetections(detections);
//   f.filter(static_cloud);            // people's points become NaN (organized) or are dropped
#include <cmath>
#include <limits>

#include <pcl/filters/filter.h>
#include <pcl/point_cloud.h>

#include "pf2/core/error.h"
#include "pf2/filters/dual_bbox_filter.h"

namespace pf2 {

// NOT thread safe (one filter instance keeps the last result, and the temporal state).
template <typename PointT>
class PclDualBBoxFilter : public pcl::Filter<PointT> {
 public:
  using PointCloud = typename pcl::Filter<PointT>::PointCloud;

  PclDualBBoxFilter() : filter_(DualBBoxFilter::Options()) { this->filter_name_ = "PclDualBBoxFilter"; }
  explicit PclDualBBoxFilter(const DualBBoxFilter::Options& options) : filter_(options) {
    this->filter_name_ = "PclDualBBoxFilter";
  }

  // The detections of the frame the next filter() call sees.
  void setDetections(const Detections& detections) { detections_ = detections; }
  // The paper's parameters (defaults: lambda 1.2, margins 0.1 m / 0.2 m, confidence 0.5).
  void setBoxScale(double lambda) { change([&](DualBBoxFilter::Options& o) { o.box_scale = lambda; }); }
  void setBackgroundMargin(double metres) {
    change([&](DualBBoxFilter::Options& o) { o.background_margin = metres; });
  }
  void setHumanMargin(double metres) { change([&](DualBBoxFilter::Options& o) { o.human_margin = metres; }); }
  void setMinConfidence(double score) { change([&](DualBBoxFilter::Options& o) { o.min_confidence = score; }); }
  // Every other knob (the additions, the histograms).
  void setOptions(const DualBBoxFilter::Options& options) { filter_.setOptions(options); }
  // true (default): removed points become NaN and the cloud stays organized; false: they are dropped.
  void setKeepOrganized(bool keep) { keep_organized_ = keep; }
  // The image-path result of the last filter() call (D_b, D_h^t, masks).
  const DualBBoxFilter::Result& result() const { return result_; }

 protected:
  void applyFilter(PointCloud& output) override {
    const PointCloud& input = *this->input_;
    if (input.height <= 1) throw Error("PclDualBBoxFilter: the input cloud must be organized");
    cv::Mat depth(static_cast<int>(input.height), static_cast<int>(input.width), CV_32F);
    for (int v = 0; v < depth.rows; ++v) {
      for (int u = 0; u < depth.cols; ++u) {
        const float z = input.at(u, v).z;
        depth.at<float>(v, u) = std::isfinite(z) && z > 0.f ? z : 0.f;
      }
    }
    result_ = filter_.filter(depth, detections_);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    output = input;
    for (int v = 0; v < depth.rows; ++v) {
      for (int u = 0; u < depth.cols; ++u) {
        if (result_.removed.at<uint8_t>(v, u)) {
          PointT& p = output.at(u, v);
          p.x = p.y = p.z = nan;
          output.is_dense = false;
        }
      }
    }
    if (!keep_organized_) {
      PointCloud dense;
      dense.header = output.header;
      for (const PointT& p : output.points) {
        if (std::isfinite(p.z)) dense.push_back(p);
      }
      output = std::move(dense);
    }
  }

 private:
  template <typename Change>
  void change(Change apply) {
    DualBBoxFilter::Options o = filter_.options();
    apply(o);
    filter_.setOptions(o);
  }

  DualBBoxFilter filter_;
  Detections detections_;
  bool keep_organized_ = true;
  DualBBoxFilter::Result result_;
};

}  // namespace pf2
