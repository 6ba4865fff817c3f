#pragma once
// NumPy .npy arrays and .npz archives (a zip of .npy files), enough to read SMPL-format model files
// and to write our own. Supported: little-endian (or single-byte) bool, int8/16/32/64,
// uint8/16/32/64, float32/64; C or Fortran order (Fortran is reordered to C on conversion).
// Rejected with a pf2::Error naming the file and the array: big-endian data, object arrays
// (pickles), bad headers, data of the wrong length, corrupt or truncated zips.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace pf2 {

struct NpyArray {
  std::string descr = "<f4";         // NumPy dtype string, e.g. "<f4", "<i8", "|u1"
  bool fortran_order = false;
  std::vector<std::size_t> shape;    // empty = scalar
  std::vector<unsigned char> bytes;  // raw element data, in the order fortran_order says

  std::size_t elementCount() const;
  std::size_t itemSize() const;      // bytes per element (from descr)
  bool isFloat() const;              // float32 or float64
  bool isInteger() const;            // any supported integer or bool type
  // All elements converted to double, in C (row-major) order. Throws pf2::Error("<where>: ...")
  // on an unsupported dtype; `where` names the file and array in the message.
  std::vector<double> toDoubles(const std::string& where) const;

  static NpyArray fromFloats(std::vector<std::size_t> shape, const std::vector<float>& values);
  static NpyArray fromInt32(std::vector<std::size_t> shape, const std::vector<std::int32_t>& values);
};

// Parses a whole .npy file held in memory. Throws pf2::Error("<where>: ...") on any problem.
NpyArray parseNpy(const std::string& data, const std::string& where);
// The .npy file (format 1.0) for an array.
std::string serializeNpy(const NpyArray& array);

// Read access to the arrays of an .npz archive; each array is inflated when asked for.
// NOT thread safe (libzip handles are not); use one reader per thread.
class NpzReader {
 public:
  // Throws pf2::Error naming the path when it is missing or not a readable zip.
  explicit NpzReader(const std::string& path);
  ~NpzReader();
  NpzReader(const NpzReader&) = delete;
  NpzReader& operator=(const NpzReader&) = delete;

  const std::string& path() const { return path_; }
  // Array names without the ".npy" suffix, in archive order.
  const std::vector<std::string>& names() const { return names_; }
  bool has(const std::string& name) const;
  // Throws pf2::Error "<path>: array '<name>': ..." when missing, unreadable or malformed.
  NpyArray read(const std::string& name) const;

 private:
  std::string path_;
  void* archive_ = nullptr;  // zip_t*, kept out of the header
  std::vector<std::string> names_;
};

// Writes an .npz (deflate-compressed, fixed timestamps so equal content gives equal bytes)
// atomically. Throws pf2::Error naming the path on failure. Thread safe for distinct paths.
void writeNpz(const std::string& path, const std::vector<std::pair<std::string, NpyArray>>& arrays);

}  // namespace pf2
