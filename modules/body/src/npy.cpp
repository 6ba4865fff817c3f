#include "pf2/body/npy.h"

#include <zip.h>
#include <zlib.h>

#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>

#include "pf2/core/atomic_file.h"
#include "pf2/core/error.h"

namespace pf2 {
namespace {

constexpr char kMagic[] = "\x93NUMPY";
constexpr std::size_t kMagicLength = 6;

struct DtypeInfo {
  char kind = 0;       // 'f', 'i', 'u', 'b'
  std::size_t size = 0;
};

DtypeInfo dtypeInfo(const std::string& descr, const std::string& where) {
  if (descr.size() >= 2 && descr[1] == 'O') throw Error(where + ": object arrays (pickles) are not supported");
  if (descr.size() < 3) throw Error(where + ": unsupported dtype '" + descr + "'");
  const char order = descr[0];
  const char kind = descr[1];
  std::size_t size = 0;
  for (std::size_t i = 2; i < descr.size(); ++i) {
    if (descr[i] < '0' || descr[i] > '9' || size > 16) {
      throw Error(where + ": unsupported dtype '" + descr + "'");
    }
    size = size * 10 + static_cast<std::size_t>(descr[i] - '0');
  }
  const bool known = (kind == 'f' && (size == 4 || size == 8)) ||
                     ((kind == 'i' || kind == 'u') && (size == 1 || size == 2 || size == 4 || size == 8)) ||
                     (kind == 'b' && size == 1);
  if (!known) throw Error(where + ": unsupported dtype '" + descr + "'");
  if (order == '>' && size > 1) throw Error(where + ": big-endian data ('" + descr + "') is not supported");
  if (order != '<' && order != '|' && order != '=' && !(order == '>' && size == 1)) {
    throw Error(where + ": unsupported dtype '" + descr + "'");
  }
  if (order == '|' && size != 1) throw Error(where + ": unsupported dtype '" + descr + "'");
  return {kind, size};
}

template <typename T>
T loadLittleEndian(const unsigned char* p) {
  // The build targets little-endian machines (x86-64, arm64); memcpy keeps it alignment-safe.
  T value;
  std::memcpy(&value, p, sizeof(T));
  return value;
}

double elementAsDouble(const unsigned char* p, const DtypeInfo& info) {
  switch (info.kind) {
    case 'f':
      return info.size == 4 ? loadLittleEndian<float>(p) : loadLittleEndian<double>(p);
    case 'i':
      switch (info.size) {
        case 1: return loadLittleEndian<std::int8_t>(p);
        case 2: return loadLittleEndian<std::int16_t>(p);
        case 4: return loadLittleEndian<std::int32_t>(p);
        default: return static_cast<double>(loadLittleEndian<std::int64_t>(p));
      }
    case 'u':
      switch (info.size) {
        case 1: return loadLittleEndian<std::uint8_t>(p);
        case 2: return loadLittleEndian<std::uint16_t>(p);
        case 4: return loadLittleEndian<std::uint32_t>(p);
        default: return static_cast<double>(loadLittleEndian<std::uint64_t>(p));
      }
    default:
      return *p != 0 ? 1.0 : 0.0;
  }
}

// Position just after `key` and the following ':' in the header dict, or npos.
std::size_t findValue(const std::string& header, const std::string& key) {
  for (const char quote : {'\'', '"'}) {
    const std::string quoted = std::string(1, quote) + key + quote;
    std::size_t at = header.find(quoted);
    if (at == std::string::npos) continue;
    at += quoted.size();
    while (at < header.size() && header[at] == ' ') ++at;
    if (at < header.size() && header[at] == ':') return at + 1;
  }
  return std::string::npos;
}

void skipSpaces(const std::string& s, std::size_t* at) {
  while (*at < s.size() && (s[*at] == ' ' || s[*at] == '\t')) ++*at;
}

}  // namespace

std::size_t NpyArray::elementCount() const {
  // Saturates instead of wrapping around, so a corrupt shape can never match a small buffer.
  std::size_t count = 1;
  for (const std::size_t d : shape) {
    if (d != 0 && count > (std::size_t{1} << 40) / d) return std::size_t{1} << 40;
    count *= d;
  }
  return count;
}

std::size_t NpyArray::itemSize() const { return dtypeInfo(descr, "npy").size; }

bool NpyArray::isFloat() const { return descr.size() > 1 && descr[1] == 'f'; }

bool NpyArray::isInteger() const {
  return descr.size() > 1 && (descr[1] == 'i' || descr[1] == 'u' || descr[1] == 'b');
}

std::vector<double> NpyArray::toDoubles(const std::string& where) const {
  const DtypeInfo info = dtypeInfo(descr, where);
  const std::size_t count = elementCount();
  if (bytes.size() != count * info.size) {
    throw Error(where + ": data holds " + std::to_string(bytes.size()) + " bytes, shape needs " +
                std::to_string(count * info.size));
  }
  std::vector<double> values(count);
  if (!fortran_order || shape.size() < 2) {
    for (std::size_t i = 0; i < count; ++i) values[i] = elementAsDouble(&bytes[i * info.size], info);
    return values;
  }
  // Fortran order: the first index varies fastest in memory. Walk the memory in order and
  // scatter each element to its row-major position.
  const std::size_t dims = shape.size();
  std::vector<std::size_t> c_strides(dims, 1);
  for (std::size_t d = dims - 1; d > 0; --d) c_strides[d - 1] = c_strides[d] * shape[d];
  std::vector<std::size_t> index(dims, 0);
  for (std::size_t i = 0; i < count; ++i) {
    std::size_t c_position = 0;
    for (std::size_t d = 0; d < dims; ++d) c_position += index[d] * c_strides[d];
    values[c_position] = elementAsDouble(&bytes[i * info.size], info);
    for (std::size_t d = 0; d < dims; ++d) {
      if (++index[d] < shape[d]) break;
      index[d] = 0;
    }
  }
  return values;
}

NpyArray NpyArray::fromFloats(std::vector<std::size_t> shape, const std::vector<float>& values) {
  NpyArray array;
  array.descr = "<f4";
  array.shape = std::move(shape);
  if (values.size() != array.elementCount()) throw Error("NpyArray::fromFloats: size does not match shape");
  array.bytes.resize(values.size() * sizeof(float));
  if (!values.empty()) std::memcpy(array.bytes.data(), values.data(), array.bytes.size());
  return array;
}

NpyArray NpyArray::fromInt32(std::vector<std::size_t> shape, const std::vector<std::int32_t>& values) {
  NpyArray array;
  array.descr = "<i4";
  array.shape = std::move(shape);
  if (values.size() != array.elementCount()) throw Error("NpyArray::fromInt32: size does not match shape");
  array.bytes.resize(values.size() * sizeof(std::int32_t));
  if (!values.empty()) std::memcpy(array.bytes.data(), values.data(), array.bytes.size());
  return array;
}

NpyArray parseNpy(const std::string& data, const std::string& where) {
  if (data.size() < kMagicLength + 4 || data.compare(0, kMagicLength, kMagic, kMagicLength) != 0) {
    throw Error(where + ": not a .npy array (bad magic)");
  }
  const unsigned major = static_cast<unsigned char>(data[6]);
  std::size_t header_length = 0;
  std::size_t header_start = 0;
  if (major == 1) {
    header_length = static_cast<unsigned char>(data[8]) | (static_cast<unsigned char>(data[9]) << 8);
    header_start = 10;
  } else if (major == 2 || major == 3) {
    if (data.size() < 12) throw Error(where + ": truncated .npy header");
    header_length = loadLittleEndian<std::uint32_t>(reinterpret_cast<const unsigned char*>(&data[8]));
    header_start = 12;
  } else {
    throw Error(where + ": unsupported .npy format version " + std::to_string(major));
  }
  if (header_length > data.size() - header_start) throw Error(where + ": truncated .npy header");
  const std::string header = data.substr(header_start, header_length);

  NpyArray array;
  std::size_t at = findValue(header, "descr");
  if (at == std::string::npos) throw Error(where + ": .npy header has no 'descr'");
  skipSpaces(header, &at);
  if (at >= header.size() || (header[at] != '\'' && header[at] != '"')) {
    throw Error(where + ": .npy header 'descr' is not a plain dtype string (structured arrays are not supported)");
  }
  const std::size_t end = header.find(header[at], at + 1);
  if (end == std::string::npos) throw Error(where + ": malformed .npy header");
  array.descr = header.substr(at + 1, end - at - 1);
  const DtypeInfo info = dtypeInfo(array.descr, where);

  at = findValue(header, "fortran_order");
  if (at == std::string::npos) throw Error(where + ": .npy header has no 'fortran_order'");
  skipSpaces(header, &at);
  if (header.compare(at, 4, "True") == 0) {
    array.fortran_order = true;
  } else if (header.compare(at, 5, "False") == 0) {
    array.fortran_order = false;
  } else {
    throw Error(where + ": malformed 'fortran_order' in .npy header");
  }

  at = findValue(header, "shape");
  if (at == std::string::npos) throw Error(where + ": .npy header has no 'shape'");
  skipSpaces(header, &at);
  if (at >= header.size() || header[at] != '(') throw Error(where + ": malformed 'shape' in .npy header");
  ++at;
  std::size_t count = 1;
  while (true) {
    skipSpaces(header, &at);
    if (at >= header.size()) throw Error(where + ": malformed 'shape' in .npy header");
    if (header[at] == ')') break;
    if (header[at] < '0' || header[at] > '9') throw Error(where + ": malformed 'shape' in .npy header");
    std::size_t value = 0;
    while (at < header.size() && header[at] >= '0' && header[at] <= '9') {
      if (value > (std::numeric_limits<std::size_t>::max() - 9) / 10) {
        throw Error(where + ": 'shape' in .npy header is too large");
      }
      value = value * 10 + static_cast<std::size_t>(header[at++] - '0');
    }
    if (value != 0 && count > std::numeric_limits<std::size_t>::max() / value / info.size) {
      throw Error(where + ": 'shape' in .npy header is too large");
    }
    count *= value;
    array.shape.push_back(value);
    skipSpaces(header, &at);
    if (at < header.size() && header[at] == ',') ++at;
  }

  const std::size_t data_start = header_start + header_length;
  const std::size_t available = data.size() - data_start;
  if (available != count * info.size) {
    throw Error(where + ": data holds " + std::to_string(available) + " bytes, shape and dtype need " +
                std::to_string(count * info.size) + (available < count * info.size ? " (truncated)" : ""));
  }
  array.bytes.assign(data.begin() + static_cast<std::ptrdiff_t>(data_start), data.end());
  return array;
}

std::string serializeNpy(const NpyArray& array) {
  std::string header = "{'descr': '" + array.descr + "', 'fortran_order': " +
                       (array.fortran_order ? "True" : "False") + ", 'shape': (";
  for (std::size_t i = 0; i < array.shape.size(); ++i) {
    header += std::to_string(array.shape[i]);
    if (array.shape.size() == 1 || i + 1 < array.shape.size()) header += ",";
    if (i + 1 < array.shape.size()) header += " ";
  }
  header += "), }";
  // Pad with spaces and end with '\n' so that the data starts at a multiple of 64 bytes.
  const std::size_t unpadded = kMagicLength + 4 + header.size() + 1;
  header.append((64 - unpadded % 64) % 64, ' ');
  header += '\n';
  if (header.size() > 65535) throw Error("serializeNpy: header too long");
  std::string out(kMagic, kMagicLength);
  out += '\x01';
  out += '\x00';
  out += static_cast<char>(header.size() & 0xff);
  out += static_cast<char>((header.size() >> 8) & 0xff);
  out += header;
  out.append(reinterpret_cast<const char*>(array.bytes.data()), array.bytes.size());
  return out;
}

NpzReader::NpzReader(const std::string& path) : path_(path) {
  int error_code = 0;
  zip_t* archive = zip_open(path.c_str(), ZIP_RDONLY, &error_code);
  if (archive == nullptr) {
    zip_error_t error;
    zip_error_init_with_code(&error, error_code);
    const std::string reason = zip_error_strerror(&error);
    zip_error_fini(&error);
    throw fileError(path, "cannot open as .npz: " + reason);
  }
  archive_ = archive;
  const zip_int64_t entries = zip_get_num_entries(archive, 0);
  for (zip_int64_t i = 0; i < entries; ++i) {
    const char* name = zip_get_name(archive, static_cast<zip_uint64_t>(i), 0);
    if (name == nullptr) continue;
    std::string array_name = name;
    if (array_name.size() > 4 && array_name.compare(array_name.size() - 4, 4, ".npy") == 0) {
      array_name.resize(array_name.size() - 4);
    }
    names_.push_back(array_name);
  }
}

NpzReader::~NpzReader() {
  if (archive_ != nullptr) zip_discard(static_cast<zip_t*>(archive_));
}

bool NpzReader::has(const std::string& name) const {
  for (const auto& n : names_) {
    if (n == name) return true;
  }
  return false;
}

NpyArray NpzReader::read(const std::string& name) const {
  const std::string where = path_ + ": array '" + name + "'";
  zip_t* archive = static_cast<zip_t*>(archive_);
  zip_int64_t index = zip_name_locate(archive, (name + ".npy").c_str(), 0);
  if (index < 0) index = zip_name_locate(archive, name.c_str(), 0);
  if (index < 0) throw Error(where + ": missing");
  zip_stat_t stat;
  zip_stat_init(&stat);
  if (zip_stat_index(archive, static_cast<zip_uint64_t>(index), 0, &stat) != 0 ||
      (stat.valid & ZIP_STAT_SIZE) == 0) {
    throw Error(where + ": cannot read its zip entry: " + zip_strerror(archive));
  }
  // A corrupt size field must not make us allocate without bound: a body model's largest array is
  // tens of megabytes, and deflate expands at most about 1030 times.
  constexpr zip_uint64_t kMaxEntryBytes = zip_uint64_t{1} << 30;
  const bool compressed_known = (stat.valid & ZIP_STAT_COMP_SIZE) != 0;
  if (stat.size > kMaxEntryBytes || (compressed_known && stat.size > 1100 * stat.comp_size + 4096)) {
    throw Error(where + ": zip entry claims " + std::to_string(stat.size) +
                " bytes, more than a model array can hold (corrupt archive?)");
  }
  std::unique_ptr<zip_file_t, int (*)(zip_file_t*)> file(
      zip_fopen_index(archive, static_cast<zip_uint64_t>(index), 0), &zip_fclose);
  if (!file) throw Error(where + ": cannot open its zip entry: " + zip_strerror(archive));
  std::string data(static_cast<std::size_t>(stat.size), '\0');
  std::size_t filled = 0;
  while (filled < data.size()) {
    const zip_int64_t got = zip_fread(file.get(), &data[filled], data.size() - filled);
    if (got < 0) throw Error(where + ": corrupt zip entry: " + zip_file_strerror(file.get()));
    if (got == 0) break;
    filled += static_cast<std::size_t>(got);
  }
  if (filled != data.size()) throw Error(where + ": zip entry is truncated");
  // libzip hands out the data even when it does not match the archive's checksum.
  if ((stat.valid & ZIP_STAT_CRC) != 0 &&
      crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(data.data()), static_cast<uInt>(data.size())) !=
          stat.crc) {
    throw Error(where + ": zip entry is corrupt (checksum mismatch)");
  }
  return parseNpy(data, where);
}

void writeNpz(const std::string& path, const std::vector<std::pair<std::string, NpyArray>>& arrays) {
  const std::string temporary_path = temporaryPathFor(path);
  int error_code = 0;
  zip_t* archive = zip_open(temporary_path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &error_code);
  if (archive == nullptr) {
    zip_error_t error;
    zip_error_init_with_code(&error, error_code);
    const std::string reason = zip_error_strerror(&error);
    zip_error_fini(&error);
    throw fileError(path, "cannot create: " + reason);
  }
  // libzip reads the buffers at zip_close, so they must live until then.
  std::vector<std::string> files;
  files.reserve(arrays.size());
  auto fail = [&](const std::string& what) {
    const std::string reason = zip_strerror(archive);
    zip_discard(archive);
    std::remove(temporary_path.c_str());
    throw fileError(path, what + ": " + reason);
  };
  for (const auto& [name, array] : arrays) {
    files.push_back(serializeNpy(array));
    zip_source_t* source = zip_source_buffer(archive, files.back().data(), files.back().size(), 0);
    if (source == nullptr) fail("cannot add array '" + name + "'");
    const zip_int64_t index = zip_file_add(archive, (name + ".npy").c_str(), source, ZIP_FL_OVERWRITE);
    if (index < 0) {
      zip_source_free(source);
      fail("cannot add array '" + name + "'");
    }
    const auto entry = static_cast<zip_uint64_t>(index);
    // 1980-01-01, the earliest zip date: the same content always gives the same bytes.
    if (zip_set_file_compression(archive, entry, ZIP_CM_DEFLATE, 9) != 0 ||
        zip_file_set_mtime(archive, entry, 315532800, 0) != 0) {
      fail("cannot set up array '" + name + "'");
    }
  }
  if (zip_close(archive) != 0) fail("cannot write");
  commitTemporaryFile(temporary_path, path);
}

}  // namespace pf2
