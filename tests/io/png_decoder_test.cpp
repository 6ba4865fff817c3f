// The datasets' PNG fast path (modules/io/src/png_decoder.h) against OpenCV's decoder.
#include "png_decoder.h"

#include <libdeflate.h>
#include <zlib.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

namespace pf2 {
namespace {

void appendBigEndian32(std::vector<unsigned char>* out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out->push_back(static_cast<unsigned char>(value >> shift));
}

void appendChunk(std::vector<unsigned char>* png, const std::string& type, const std::vector<unsigned char>& data) {
  appendBigEndian32(png, static_cast<std::uint32_t>(data.size()));
  std::vector<unsigned char> typed(type.begin(), type.end());
  typed.insert(typed.end(), data.begin(), data.end());
  png->insert(png->end(), typed.begin(), typed.end());
  appendBigEndian32(png, static_cast<std::uint32_t>(crc32(crc32(0L, Z_NULL, 0), typed.data(), typed.size())));
}

// The PNG filter `type` applied to one row (the encoder's direction), `previous` the raw row above.
std::vector<unsigned char> filterRow(int type, const unsigned char* row, const unsigned char* previous, int length,
                                     int bpp) {
  std::vector<unsigned char> out(length);
  for (int i = 0; i < length; ++i) {
    const int left = i >= bpp ? row[i - bpp] : 0, up = previous[i], up_left = i >= bpp ? previous[i - bpp] : 0;
    int predictor = 0;
    if (type == 1) predictor = left;
    if (type == 2) predictor = up;
    if (type == 3) predictor = (left + up) / 2;
    if (type == 4) {
      const int p = left + up - up_left, dl = std::abs(p - left), du = std::abs(p - up), dul = std::abs(p - up_left);
      predictor = dl <= du && dl <= dul ? left : du <= dul ? up : up_left;
    }
    out[i] = static_cast<unsigned char>(row[i] - predictor);
  }
  return out;
}

// A PNG of random samples (8-bit RGB or 16-bit grey) whose rows cycle through the five filters.
std::vector<unsigned char> handMadePng(bool colour, int width, int height, unsigned seed) {
  const int bpp = colour ? 3 : 2, stride = width * bpp;
  cv::Mat samples(height, stride, CV_8U);
  cv::RNG(seed).fill(samples, cv::RNG::UNIFORM, 0, 256);
  std::vector<unsigned char> raw, zeros(stride, 0);
  for (int v = 0; v < height; ++v) {
    const unsigned char* previous = v > 0 ? samples.ptr<unsigned char>(v - 1) : zeros.data();
    raw.push_back(static_cast<unsigned char>(v % 5));
    const std::vector<unsigned char> filtered = filterRow(v % 5, samples.ptr<unsigned char>(v), previous, stride, bpp);
    raw.insert(raw.end(), filtered.begin(), filtered.end());
  }
  libdeflate_compressor* compressor = libdeflate_alloc_compressor(6);
  std::vector<unsigned char> compressed(libdeflate_zlib_compress_bound(compressor, raw.size()));
  compressed.resize(libdeflate_zlib_compress(compressor, raw.data(), raw.size(), compressed.data(), compressed.size()));
  libdeflate_free_compressor(compressor);

  std::vector<unsigned char> png = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'}, header;
  appendBigEndian32(&header, width);
  appendBigEndian32(&header, height);
  header.insert(header.end(), {static_cast<unsigned char>(colour ? 8 : 16), static_cast<unsigned char>(colour ? 2 : 0),
                               0, 0, 0});
  appendChunk(&png, "IHDR", header);
  // Two IDAT chunks: the decoder must join them.
  const std::size_t half = compressed.size() / 2;
  appendChunk(&png, "IDAT", std::vector<unsigned char>(compressed.begin(), compressed.begin() + half));
  appendChunk(&png, "IDAT", std::vector<unsigned char>(compressed.begin() + half, compressed.end()));
  appendChunk(&png, "IEND", {});
  return png;
}

void expectSameAsOpenCv(const std::vector<unsigned char>& png, int flags, const std::string& what) {
  const cv::Mat fast = decodeDatasetPng(png, flags), reference = cv::imdecode(png, flags);
  ASSERT_FALSE(fast.empty()) << what;
  ASSERT_FALSE(reference.empty()) << what;
  ASSERT_EQ(fast.type(), reference.type()) << what;
  ASSERT_EQ(fast.size(), reference.size()) << what;
  EXPECT_EQ(cv::norm(fast, reference, cv::NORM_INF), 0.0) << what;
}

TEST(PngDecoder, EveryFilterTypeDecodesAsOpenCvDoes) {
  for (const bool colour : {true, false}) {
    const std::vector<unsigned char> png = handMadePng(colour, 37, 23, colour ? 1 : 2);
    expectSameAsOpenCv(png, colour ? cv::IMREAD_COLOR : cv::IMREAD_UNCHANGED, colour ? "RGB" : "grey 16");
  }
}

TEST(PngDecoder, OpenCvsOwnPngsDecodeTheSame) {
  cv::Mat bgr(48, 64, CV_8UC3), depth(48, 64, CV_16UC1);
  cv::RNG(3).fill(bgr, cv::RNG::UNIFORM, 0, 256);
  cv::RNG(4).fill(depth, cv::RNG::UNIFORM, 0, 65536);
  for (int level : {0, 1, 9}) {
    std::vector<unsigned char> png;
    cv::imencode(".png", bgr, png, {cv::IMWRITE_PNG_COMPRESSION, level});
    expectSameAsOpenCv(png, cv::IMREAD_COLOR, "BGR level " + std::to_string(level));
    cv::imencode(".png", depth, png, {cv::IMWRITE_PNG_COMPRESSION, level});
    expectSameAsOpenCv(png, cv::IMREAD_UNCHANGED, "depth level " + std::to_string(level));
  }
}

TEST(PngDecoder, LeavesOtherImagesAndBrokenDataToOpenCv) {
  std::vector<unsigned char> grey8, rgb;
  cv::imencode(".png", cv::Mat(8, 8, CV_8UC1, cv::Scalar(7)), grey8);
  EXPECT_TRUE(decodeDatasetPng(grey8, cv::IMREAD_COLOR).empty());  // 8-bit grey: not a dataset frame
  const std::vector<unsigned char> png = handMadePng(true, 16, 16, 5);
  EXPECT_TRUE(decodeDatasetPng(png, cv::IMREAD_GRAYSCALE).empty());  // flags it does not serve
  std::vector<unsigned char> broken = png;
  broken[broken.size() / 2] ^= 0x5a;  // inside the compressed data (the CRC is the caller's check)
  EXPECT_TRUE(decodeDatasetPng(broken, cv::IMREAD_COLOR).empty());
  EXPECT_TRUE(decodeDatasetPng(std::vector<unsigned char>(png.begin(), png.begin() + 40), cv::IMREAD_COLOR).empty());
}

// Every 15th frame of the real sequences in ../shared/data, colour and depth.
TEST(PngDecoder, RealDatasetFramesDecodeAsOpenCvDoesWhenPresent) {
  int compared = 0;
  for (const std::string sequence : {"bonn_crowd_250_150", "tum_fr1_rpy_120", "tum_fr1_desk_9"}) {
    for (const auto& [list, flags] : {std::pair<std::string, int>{"rgb.txt", cv::IMREAD_COLOR},
                                      std::pair<std::string, int>{"depth.txt", cv::IMREAD_UNCHANGED}}) {
      const std::string folder = std::string(PF2_SHARED_DATA) + "/" + sequence + "/";
      std::ifstream in(folder + list);
      std::string line;
      for (int n = 0; std::getline(in, line);) {
        if (line.empty() || line[0] == '#' || n++ % 15 != 0) continue;
        std::ifstream file(folder + line.substr(line.find(' ') + 1), std::ios::binary);
        const std::vector<unsigned char> png((std::istreambuf_iterator<char>(file)), {});
        expectSameAsOpenCv(png, flags, sequence + " " + line);
        ++compared;
      }
    }
  }
  if (compared == 0) GTEST_SKIP() << "no shared data";
  EXPECT_GT(compared, 20);
}

}  // namespace
}  // namespace pf2
