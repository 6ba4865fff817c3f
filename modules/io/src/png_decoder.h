#pragma once
// A fast path for the PNG frames of recorded RGB-D datasets (TUM, Bonn, pf2_synth): 8-bit RGB
// colour and 16-bit grey depth, not interlaced. The compressed stream is inflated with libdeflate
// (about 2.5 times faster than zlib's inflate, which was 9 % of a run's CPU), the rows unfiltered
// here. Anything else (other formats, flags, corrupt data) returns an empty Mat so the caller
// falls back to cv::imdecode, which then gives its own result or error. Thread safe.
#include <vector>

#include <opencv2/core.hpp>

namespace pf2 {

// `bytes`: a whole PNG file whose chunks were already walked and CRC-checked. flags: the
// cv::imread flags the caller wants; only cv::IMREAD_COLOR on 8-bit RGB (gives BGR CV_8UC3) and
// cv::IMREAD_UNCHANGED on 16-bit grey (gives CV_16UC1) are decoded here. The result equals
// cv::imdecode's to the byte.
cv::Mat decodeDatasetPng(const std::vector<unsigned char>& bytes, int flags);

}  // namespace pf2
