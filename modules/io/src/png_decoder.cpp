#include "png_decoder.h"

#include <libdeflate.h>

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <string>

#include <opencv2/imgcodecs.hpp>

namespace pf2 {
namespace {

struct PngLayout {
  int width = 0, height = 0, bit_depth = 0, colour_type = -1;
  bool interlaced = false;
  std::vector<unsigned char> compressed;  // the IDAT chunks' data, concatenated
};

// The header and the compressed data; false on anything unexpected.
bool readLayout(const std::vector<unsigned char>& bytes, PngLayout* png) {
  bool header = false;
  const auto visit = [&](const unsigned char* type, const unsigned char* data, std::uint32_t length, std::uint32_t) {
    const std::string name(reinterpret_cast<const char*>(type), 4);
    if (name == "IHDR" && length == 13) {
      png->width = static_cast<int>(bigEndian32(data));
      png->height = static_cast<int>(bigEndian32(data + 4));
      png->bit_depth = data[8];
      png->colour_type = data[9];
      png->interlaced = data[12] != 0;
      header = data[10] == 0 && data[11] == 0;  // deflate, adaptive filtering: the only ones defined
    } else if (name == "IDAT") {
      png->compressed.insert(png->compressed.end(), data, data + length);
    }
  };
  return walkPngChunks(bytes, visit) == PngWalk::kEnded && header;
}

// Paeth's predictor (PNG specification, filter type 4).
inline int paeth(int left, int up, int up_left) {
  const int p = left + up - up_left;
  const int dl = std::abs(p - left), du = std::abs(p - up), dul = std::abs(p - up_left);
  if (dl <= du && dl <= dul) return left;
  return du <= dul ? up : up_left;
}

// Undoes one row's filter in place; `previous` is the unfiltered row above (zeros for the first).
// bpp: bytes per complete pixel. False for an unknown filter type.
bool unfilterRow(int filter, unsigned char* row, const unsigned char* previous, int length, int bpp) {
  switch (filter) {
    case 0:
      return true;
    case 1:
      for (int i = bpp; i < length; ++i) row[i] = static_cast<unsigned char>(row[i] + row[i - bpp]);
      return true;
    case 2:
      for (int i = 0; i < length; ++i) row[i] = static_cast<unsigned char>(row[i] + previous[i]);
      return true;
    case 3:
      for (int i = 0; i < length; ++i) {
        const int left = i >= bpp ? row[i - bpp] : 0;
        row[i] = static_cast<unsigned char>(row[i] + ((left + previous[i]) >> 1));
      }
      return true;
    case 4:
      for (int i = 0; i < length; ++i) {
        const int left = i >= bpp ? row[i - bpp] : 0, up_left = i >= bpp ? previous[i - bpp] : 0;
        row[i] = static_cast<unsigned char>(row[i] + paeth(left, previous[i], up_left));
      }
      return true;
    default:
      return false;
  }
}

}  // namespace

cv::Mat decodeDatasetPng(const std::vector<unsigned char>& bytes, int flags) {
  PngLayout png;
  if (!readLayout(bytes, &png) || png.interlaced || png.width <= 0 || png.height <= 0) return cv::Mat();
  const bool colour = flags == cv::IMREAD_COLOR && png.colour_type == 2 && png.bit_depth == 8;
  const bool depth = flags == cv::IMREAD_UNCHANGED && png.colour_type == 0 && png.bit_depth == 16;
  if (!colour && !depth) return cv::Mat();
  const int bpp = colour ? 3 : 2;
  const std::size_t stride = static_cast<std::size_t>(png.width) * bpp;
  std::vector<unsigned char> raw(png.height * (stride + 1));
  const std::unique_ptr<libdeflate_decompressor, decltype(&libdeflate_free_decompressor)> inflater(
      libdeflate_alloc_decompressor(), &libdeflate_free_decompressor);
  std::size_t inflated = 0;
  if (!inflater || libdeflate_zlib_decompress(inflater.get(), png.compressed.data(), png.compressed.size(),
                                              raw.data(), raw.size(), &inflated) != LIBDEFLATE_SUCCESS ||
      inflated != raw.size())
    return cv::Mat();

  cv::Mat image(png.height, png.width, colour ? CV_8UC3 : CV_16UC1);
  const std::vector<unsigned char> zeros(stride, 0);
  const unsigned char* previous = zeros.data();
  for (int v = 0; v < png.height; ++v) {
    unsigned char* row = &raw[v * (stride + 1) + 1];
    if (!unfilterRow(row[-1], row, previous, static_cast<int>(stride), bpp)) return cv::Mat();
    previous = row;
  }
  // PNG stores RGB and big-endian samples; OpenCV gives BGR and native 16-bit values.
  for (int v = 0; v < png.height; ++v) {
    const unsigned char* row = &raw[v * (stride + 1) + 1];
    if (colour) {
      unsigned char* out = image.ptr<unsigned char>(v);
      for (int u = 0; u < png.width; ++u, row += 3, out += 3) {
        out[0] = row[2];
        out[1] = row[1];
        out[2] = row[0];
      }
    } else {
      std::uint16_t* out = image.ptr<std::uint16_t>(v);
      for (int u = 0; u < png.width; ++u, row += 2) out[u] = static_cast<std::uint16_t>((row[0] << 8) | row[1]);
    }
  }
  return image;
}

}  // namespace pf2
