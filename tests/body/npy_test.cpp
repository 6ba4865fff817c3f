#include "pf2/body/npy.h"

#include <cstring>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "pf2/core/error.h"

namespace pf2 {
namespace {

// A .npy file with a hand-written header (format 1.0), as NumPy would write it.
std::string npyFile(const std::string& header_dict, const std::string& data) {
  std::string header = header_dict;
  while ((10 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string out("\x93NUMPY\x01\x00", 8);
  out += static_cast<char>(header.size() & 0xff);
  out += static_cast<char>(header.size() >> 8);
  return out + header + data;
}

template <typename T>
std::string bytesOf(const std::vector<T>& values) {
  return std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void writeFile(const std::string& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << content;
}

// Expects a pf2::Error whose message contains every one of `parts`.
template <typename F>
void expectError(F&& f, const std::vector<std::string>& parts) {
  try {
    f();
    FAIL() << "no pf2::Error thrown";
  } catch (const Error& e) {
    for (const auto& part : parts) EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(Npy, Float32RoundTrip) {
  const NpyArray array = NpyArray::fromFloats({2, 3}, {1, 2, 3, 4, 5, -6.5f});
  const std::string file = serializeNpy(array);
  EXPECT_EQ(file.substr(0, 6), "\x93NUMPY");
  const std::size_t header_length = static_cast<unsigned char>(file[8]) | (static_cast<unsigned char>(file[9]) << 8);
  EXPECT_EQ((10 + header_length) % 64, 0u);  // data aligned as NumPy does
  const NpyArray back = parseNpy(file, "x");
  EXPECT_EQ(back.descr, "<f4");
  EXPECT_EQ(back.shape, (std::vector<std::size_t>{2, 3}));
  EXPECT_EQ(back.toDoubles("x"), (std::vector<double>{1, 2, 3, 4, 5, -6.5}));
}

TEST(Npy, OneDimensionalShapeHasTrailingComma) {
  const std::string file = serializeNpy(NpyArray::fromInt32({3}, {7, -8, 9}));
  EXPECT_NE(file.find("'shape': (3,)"), std::string::npos);
  EXPECT_EQ(parseNpy(file, "x").toDoubles("x"), (std::vector<double>{7, -8, 9}));
}

TEST(Npy, ReadsFloat64AndIntegerTypes) {
  const NpyArray f8 = parseNpy(
      npyFile("{'descr': '<f8', 'fortran_order': False, 'shape': (2,), }", bytesOf<double>({0.25, -1e300})), "f8");
  EXPECT_EQ(f8.toDoubles("f8"), (std::vector<double>{0.25, -1e300}));
  const NpyArray u4 = parseNpy(
      npyFile("{'descr': '<u4', 'fortran_order': False, 'shape': (2,), }", bytesOf<std::uint32_t>({4294967295u, 3})),
      "u4");
  EXPECT_EQ(u4.toDoubles("u4"), (std::vector<double>{4294967295.0, 3}));
  const NpyArray i8 = parseNpy(
      npyFile("{'descr': '<i8', 'fortran_order': False, 'shape': (1, 1), }", bytesOf<std::int64_t>({-5})), "i8");
  EXPECT_EQ(i8.toDoubles("i8"), (std::vector<double>{-5}));
  const NpyArray u1 =
      parseNpy(npyFile("{'descr': '|u1', 'fortran_order': False, 'shape': (2,), }", std::string("\x02\xff", 2)), "u1");
  EXPECT_EQ(u1.toDoubles("u1"), (std::vector<double>{2, 255}));
}

TEST(Npy, FortranOrderIsReorderedToCOrder) {
  // The 2x3 matrix [[1 2 3] [4 5 6]] stored column by column.
  const NpyArray array = parseNpy(npyFile("{'descr': '<f8', 'fortran_order': True, 'shape': (2, 3), }",
                                          bytesOf<double>({1, 4, 2, 5, 3, 6})),
                                  "F");
  EXPECT_TRUE(array.fortran_order);
  EXPECT_EQ(array.toDoubles("F"), (std::vector<double>{1, 2, 3, 4, 5, 6}));
  // 3-d: shape (2, 2, 2), element (i, j, k) = 100 i + 10 j + k; Fortran: i fastest.
  std::vector<double> fortran;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) fortran.push_back(100 * i + 10 * j + k);
  const NpyArray cube = parseNpy(
      npyFile("{'descr': '<f8', 'fortran_order': True, 'shape': (2, 2, 2), }", bytesOf<double>(fortran)), "F3");
  EXPECT_EQ(cube.toDoubles("F3"), (std::vector<double>{0, 1, 10, 11, 100, 101, 110, 111}));
}

TEST(Npy, FormatVersion2Header) {
  std::string header = "{'descr': '<f4', 'fortran_order': False, 'shape': (1,), }";
  while ((12 + header.size() + 1) % 64 != 0) header += ' ';
  header += '\n';
  std::string file("\x93NUMPY\x02\x00", 8);
  const std::uint32_t length = static_cast<std::uint32_t>(header.size());
  file += std::string(reinterpret_cast<const char*>(&length), 4) + header + bytesOf<float>({3.5f});
  EXPECT_EQ(parseNpy(file, "v2").toDoubles("v2"), (std::vector<double>{3.5}));
}

TEST(Npy, BrokenFilesThrowWithTheName) {
  const std::string good = npyFile("{'descr': '<f4', 'fortran_order': False, 'shape': (2,), }", bytesOf<float>({1, 2}));
  expectError([&] { parseNpy("garbage that is not npy", "m.npz: array 'a'"); }, {"m.npz: array 'a'", "magic"});
  expectError([&] { parseNpy(good.substr(0, good.size() - 3), "a"); }, {"a:", "truncated"});
  expectError([&] { parseNpy(good.substr(0, 20), "a"); }, {"a:", "header"});
  expectError([&] { parseNpy(good + "xx", "a"); }, {"a:", "bytes"});
  expectError(
      [&] { parseNpy(npyFile("{'descr': '>f4', 'fortran_order': False, 'shape': (1,), }", "abcd"), "be"); },
      {"be:", "big-endian"});
  expectError([&] { parseNpy(npyFile("{'descr': '|O', 'fortran_order': False, 'shape': (1,), }", "abcdefgh"), "o"); },
              {"o:", "object"});
  expectError([&] { parseNpy(npyFile("{'descr': '<c8', 'fortran_order': False, 'shape': (1,), }", "abcdefgh"), "c"); },
              {"c:", "dtype"});
  expectError([&] { parseNpy(npyFile("{'descr': '<f4', 'shape': (1,), }", "abcd"), "n"); }, {"fortran_order"});
  expectError([&] { parseNpy(npyFile("{'descr': '<f4', 'fortran_order': False, 'shape': (1, x), }", "abcd"), "s"); },
              {"shape"});
  expectError(
      [&] {
        parseNpy(npyFile("{'descr': '<f4', 'fortran_order': False, 'shape': (4294967296, 4294967296, 4294967296), }",
                         "abcd"),
                 "huge");
      },
      {"huge:", "too large"});
  expectError([&] { parseNpy(npyFile("{'descr': [('a', '<f4')], 'fortran_order': False, 'shape': (1,), }", "abcd"), "st"); },
              {"structured"});
}

TEST(Npz, WriteReadAndMissingArray) {
  const std::string path = testing::TempDir() + "pf2_npz_roundtrip.npz";
  writeNpz(path, {{"a", NpyArray::fromFloats({2}, {1.5f, 2.5f})}, {"b", NpyArray::fromInt32({1}, {42})}});
  const NpzReader npz(path);
  EXPECT_EQ(npz.names(), (std::vector<std::string>{"a", "b"}));
  EXPECT_TRUE(npz.has("a"));
  EXPECT_FALSE(npz.has("c"));
  EXPECT_EQ(npz.read("a").toDoubles("a"), (std::vector<double>{1.5, 2.5}));
  EXPECT_EQ(npz.read("b").toDoubles("b"), (std::vector<double>{42}));
  expectError([&] { npz.read("c"); }, {path, "'c'", "missing"});
}

TEST(Npz, SameContentGivesSameBytes) {
  const std::string a = testing::TempDir() + "pf2_npz_same_a.npz";
  const std::string b = testing::TempDir() + "pf2_npz_same_b.npz";
  writeNpz(a, {{"x", NpyArray::fromFloats({3}, {1, 2, 3})}});
  writeNpz(b, {{"x", NpyArray::fromFloats({3}, {1, 2, 3})}});
  EXPECT_EQ(readFile(a), readFile(b));
}

TEST(Npz, BrokenArchivesThrowWithThePath) {
  const std::string dir = testing::TempDir();
  expectError([&] { NpzReader r(dir + "pf2_no_such_file.npz"); }, {"pf2_no_such_file.npz"});
  const std::string garbage = dir + "pf2_garbage.npz";
  writeFile(garbage, std::string(1000, 'x'));
  expectError([&] { NpzReader r(garbage); }, {garbage});

  // A real archive cut at every length must throw (at open or read), never crash.
  const std::string whole = dir + "pf2_whole.npz";
  std::vector<float> values(5000);
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<float>(i % 97) * 0.5f;
  writeNpz(whole, {{"a", NpyArray::fromFloats({values.size()}, values)}});
  const std::string bytes = readFile(whole);
  const std::string cut = dir + "pf2_cut.npz";
  int thrown = 0;
  for (std::size_t length = 0; length < bytes.size(); length += 97) {
    writeFile(cut, bytes.substr(0, length));
    try {
      NpzReader r(cut);
      r.read("a");
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find(cut), std::string::npos) << e.what();
      ++thrown;
    }
  }
  EXPECT_EQ(thrown, static_cast<int>((bytes.size() + 96) / 97));

  // Flipped bytes inside the compressed data: CRC or inflate errors name the array.
  std::string corrupt = bytes;
  for (std::size_t i = 60; i < 200; i += 7) corrupt[i] = static_cast<char>(corrupt[i] ^ 0x5a);
  writeFile(cut, corrupt);
  expectError(
      [&] {
        NpzReader r(cut);
        const NpyArray a = r.read("a");
        // If the damage left a valid stream the values must differ; count that as detected too.
        if (a.toDoubles("a") != std::vector<double>(values.begin(), values.end())) throw Error(cut + ": 'a' changed");
      },
      {cut});
}

}  // namespace
}  // namespace pf2
