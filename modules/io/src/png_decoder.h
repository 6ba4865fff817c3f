#pragma once
// A fast path for the PNG frames of recorded RGB-D datasets (TUM, Bonn, pf2_synth): 8-bit RGB
// colour and 16-bit grey depth, not interlaced. The compressed stream is inflated with libdeflate
// (about 2.5 times faster than zlib's inflate, which was 9 % of a run's CPU), the rows unfiltered
// here. Anything else (other formats, flags, corrupt data) returns an empty Mat so the caller
// falls back to cv::imdecode, which then gives its own result or error. Thread safe.
#include <cstdint>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace pf2 {

inline std::uint32_t bigEndian32(const unsigned char* p) {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

// How a walk through a PNG's chunks ended.
enum class PngWalk { kEnded, kTruncated, kOverrun };

// Calls visit(type, data, length, stored_crc) for every chunk after the 8-byte signature, up to and
// including IEND. kTruncated: the file ends inside a chunk's header or CRC; kOverrun: a chunk's
// length runs past the file's end (nothing is visited beyond either). `type` points at the chunk's
// 4 type bytes, `data` at its data; both point into `bytes`.
template <typename Visit>
PngWalk walkPngChunks(const std::vector<unsigned char>& bytes, Visit visit) {
  for (std::size_t at = 8;;) {
    if (at + 12 > bytes.size()) return PngWalk::kTruncated;
    const std::uint32_t length = bigEndian32(&bytes[at]);
    if (length > bytes.size() - at - 12) return PngWalk::kOverrun;
    const unsigned char* type = &bytes[at + 4];
    visit(type, type + 4, length, bigEndian32(type + 4 + length));
    if (std::string(reinterpret_cast<const char*>(type), 4) == "IEND") return PngWalk::kEnded;
    at += 12 + length;
  }
}

// `bytes`: a whole PNG file whose chunks were already walked and CRC-checked. flags: the
// cv::imread flags the caller wants; only cv::IMREAD_COLOR on 8-bit RGB (gives BGR CV_8UC3) and
// cv::IMREAD_UNCHANGED on 16-bit grey (gives CV_16UC1) are decoded here. The result equals
// cv::imdecode's to the byte.
cv::Mat decodeDatasetPng(const std::vector<unsigned char>& bytes, int flags);

}  // namespace pf2
