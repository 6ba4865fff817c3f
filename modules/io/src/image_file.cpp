#include "pf2/io/image_file.h"

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"
#include "png_decoder.h"

namespace pf2 {

namespace {

constexpr int kMaxSide = 16384;

// Walks the PNG's chunks up to IEND; returns the IHDR size. Throws naming the path and the fault.
cv::Size checkPng(const std::string& path, const std::vector<unsigned char>& bytes, const std::string& what) {
  cv::Size size;
  const auto visit = [&](const unsigned char* type, const unsigned char* data, std::uint32_t length,
                         std::uint32_t crc) {
    if (crc32(crc32(0L, Z_NULL, 0), type, length + 4) != crc)
      throw fileError(path, what + " is corrupt (PNG chunk CRC mismatch)");
    if (std::string(reinterpret_cast<const char*>(type), 4) == "IHDR" && length >= 8) {
      const std::uint32_t width = bigEndian32(data), height = bigEndian32(data + 4);
      if (width > kMaxSide || height > kMaxSide) {
        throw fileError(path, what + " is " + std::to_string(width) + "x" + std::to_string(height) +
                                  ", larger than 16384 pixels a side");
      }
      size = cv::Size(static_cast<int>(width), static_cast<int>(height));
    }
  };
  const PngWalk walk = walkPngChunks(bytes, visit);
  if (walk == PngWalk::kTruncated) throw fileError(path, what + " is truncated (PNG ends inside a chunk)");
  if (walk == PngWalk::kOverrun)
    throw fileError(path, what + " is truncated or corrupt (a PNG chunk runs past its end)");
  if (size.area() == 0) throw fileError(path, what + " is corrupt (PNG without an image header)");
  return size;
}

}  // namespace

cv::Mat readImageFile(const std::string& path, int flags, const std::string& what, const cv::Size& expected) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) throw fileError(path, "is a folder, not a " + what);
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) throw fileError(path, "missing or unreadable " + what);
  std::vector<unsigned char> bytes(static_cast<size_t>(std::max<std::streamoff>(0, in.tellg())));
  in.seekg(0);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()))) {
    throw fileError(path, "missing or unreadable " + what);
  }
  static const unsigned char kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  cv::Mat image;
  if (bytes.size() >= 8 && std::equal(kPngSignature, kPngSignature + 8, bytes.begin())) {
    const cv::Size size = checkPng(path, bytes, what);
    if (!expected.empty() && size != expected) {
      throw fileError(path, what + " is " + std::to_string(size.width) + "x" + std::to_string(size.height) +
                                ", expected " + std::to_string(expected.width) + "x" + std::to_string(expected.height));
    }
    image = decodeDatasetPng(bytes, flags);  // the datasets' PNGs, faster; empty for anything else
  }
  try {
    if (image.empty()) image = cv::imdecode(bytes, flags);
  } catch (const cv::Exception&) {
    image.release();
  }
  if (image.empty()) throw fileError(path, "missing or unreadable " + what);
  return image;
}

void writeImageFile(const std::string& path, const cv::Mat& image) {
  const auto dot = path.find_last_of('.');
  const std::string extension = dot == std::string::npos ? "" : path.substr(dot);
  std::vector<unsigned char> bytes;
  bool encoded = false;
  try {
    encoded = cv::imencode(extension, image, bytes);
  } catch (const cv::Exception&) {
    encoded = false;
  }
  if (!encoded) throw fileError(path, "cannot encode the image as '" + extension + "'");
  writeFileAtomically(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  });
}

}  // namespace pf2
