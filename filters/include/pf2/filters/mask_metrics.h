#pragma once
// How well a static depth image has had its people removed, against a ground-truth person mask.
// Counted over pixels with a measured input depth only (a pixel without depth cannot be kept):
//   recall     = person pixels removed from the static depth / person pixels          (want 1)
//   precision  = static pixels kept / all pixels kept in the static depth              (want 1)
//   retention  = static pixels kept / static pixels                                    (want 1)
// Removing a static pixel costs retention, never precision; report both so that removing
// everything cannot look good.
#include <cstdint>

#include <opencv2/core.hpp>

namespace pf2 {

struct MaskCounts {
  int64_t person = 0;          // ground-truth person pixels with depth
  int64_t person_removed = 0;  // ... of which removed from the static depth
  int64_t static_total = 0;    // static pixels with depth
  int64_t static_kept = 0;     // ... of which kept
  int64_t frames = 0;

  double recall() const { return person ? static_cast<double>(person_removed) / person : 1.0; }
  double precision() const {
    const int64_t kept = static_kept + (person - person_removed);
    return kept ? static_cast<double>(static_kept) / kept : 1.0;
  }
  double retention() const { return static_total ? static_cast<double>(static_kept) / static_total : 1.0; }
  MaskCounts& operator+=(const MaskCounts& other);
};

// Counts one frame. input_depth and static_depth are CV_32F metres (0/NaN = none);
// person_mask is CV_8U or CV_16U, non-zero = person (pf2_synth's gt/masks ids work as they are).
// Throws pf2::Error when the images differ in size or type. Thread safe.
MaskCounts countMaskAgreement(const cv::Mat& input_depth, const cv::Mat& static_depth,
                              const cv::Mat& person_mask);

// The mask moved dx pixels right (left for dx < 0), zeros shifted in: a ground-truth person mask
// brought onto depth that lies dx pixels right of it (pf2_synth --misalign). Thread safe.
cv::Mat shiftMaskRight(const cv::Mat& mask, int dx);

}  // namespace pf2
