#include "pf2/core/command_line.h"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <new>
#include <string>

#include <opencv2/core/utils/logger.hpp>

#include "pf2/core/error.h"

namespace pf2 {

CommandLine::CommandLine(int argc, const char* const* argv) {
  for (int i = 1; i < argc; ++i) args_.emplace_back(argv[i]);
  used_.assign(args_.size(), false);
}

bool CommandLine::helpRequested() const {
  for (const std::string& a : args_) {
    if (a == "-h" || a == "--help") return true;
  }
  return false;
}

bool CommandLine::flag(const std::string& name) {
  bool found = false;
  for (size_t i = 0; i < args_.size(); ++i) {
    if (!used_[i] && args_[i] == name) used_[i] = found = true;
  }
  return found;
}

bool CommandLine::has(const std::string& name) const {
  for (size_t i = 0; i < args_.size(); ++i) {
    if (!used_[i] && args_[i] == name) return true;
  }
  return false;
}

std::vector<std::string> CommandLine::values(const std::string& name) {
  std::vector<std::string> result;
  for (size_t i = 0; i < args_.size(); ++i) {
    if (used_[i] || args_[i] != name) continue;
    if (i + 1 >= args_.size()) throw Error("option " + name + " needs a value");
    used_[i] = used_[i + 1] = true;
    result.push_back(args_[i + 1]);
  }
  return result;
}

std::optional<std::string> CommandLine::value(const std::string& name) {
  const std::vector<std::string> all = values(name);
  if (all.empty()) return std::nullopt;
  return all.back();
}

std::string CommandLine::value(const std::string& name, const std::string& fallback) {
  return value(name).value_or(fallback);
}

double CommandLine::number(const std::string& name, double fallback) {
  const auto text = value(name);
  if (!text) return fallback;
  try {
    size_t end = 0;
    const double v = std::stod(*text, &end);
    if (end == text->size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw Error("option " + name + ": expected a number, got '" + *text + "'");
}

int CommandLine::integer(const std::string& name, int fallback) {
  const auto text = value(name);
  if (!text) return fallback;
  try {
    size_t end = 0;
    const int v = std::stoi(*text, &end);
    if (end == text->size()) return v;
  } catch (const std::exception&) {
  }
  throw Error("option " + name + ": expected an integer, got '" + *text + "'");
}

std::vector<std::string> CommandLine::positionals() {
  std::vector<std::string> result;
  for (size_t i = 0; i < args_.size(); ++i) {
    if (used_[i]) continue;
    if (args_[i].size() > 1 && args_[i][0] == '-' &&
        !std::isdigit(static_cast<unsigned char>(args_[i][1])) && args_[i][1] != '.') {
      throw Error("unknown option " + args_[i] + " (see -h)");
    }
    result.push_back(args_[i]);
  }
  return result;
}

void keepFreedImageMemory() {
#if defined(__GLIBC__)
  // glibc hands blocks above its mmap threshold (128 KB to 32 MB, adaptive) back to the kernel on
  // free and trims the heap's top, so every new 640x480 image costs ~300-400 fresh page faults;
  // in a virtual machine that measured ~4 ms per frame in the Dual-BBox filter alone (4x its
  // compute, docs/BENCHMARKS.md). Serving them from the heap and never trimming it keeps the
  // pages mapped for the next frame; peak memory is unchanged, it is just not returned early.
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
}

namespace {

// One readable line: line breaks become spaces, and a message made long by the text it quotes
// (a 10 MB line of garbage) keeps its start and end (file, line and what was expected come first).
// Control characters and bytes that are not UTF-8 (garbage quoted from a broken file) as \xNN.
std::string printable(const std::string& text) {
  std::string out;
  char escaped[8];
  for (size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    // The length of a well-formed UTF-8 sequence starting here (1 for ASCII), 0 when malformed.
    size_t length = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xe ? 3 : (c >> 3) == 0x1e ? 4 : 0;
    for (size_t k = 1; k < length; ++k) {
      if (i + k >= text.size() || (static_cast<unsigned char>(text[i + k]) >> 6) != 0x2) length = 0;
    }
    if (c == '\n' || c == '\r' || c == '\t') {
      out += ' ';
      i += 1;
    } else if (length == 0 || c < 0x20 || c == 0x7f) {
      std::snprintf(escaped, sizeof(escaped), "\\x%02X", c);
      out += escaped;
      i += 1;
    } else {
      out.append(text, i, length);
      i += length;
    }
  }
  return out;
}

std::string oneReadableLine(const std::string& raw) {
  constexpr size_t kMaxLength = 400;
  std::string message = printable(raw);
  if (message.size() <= kMaxLength) return message;
  return message.substr(0, kMaxLength - 100) + " [... " + std::to_string(message.size() - kMaxLength + 20) +
         " characters left out ...] " + message.substr(message.size() - 80);
}

}  // namespace

int runApp(const char* program, int (*body)(int, char**), int argc, char** argv) {
  keepFreedImageMemory();
  // OpenCV's own warnings (an unreadable image) would come before our one error line.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
  try {
    return body(argc, argv);
  } catch (const std::bad_alloc&) {
    std::cerr << program << ": error: out of memory (a setting or an input asks for more than this machine has)"
              << std::endl;
    return 1;
  } catch (const std::exception& e) {
    std::cerr << program << ": error: " << oneReadableLine(e.what()) << std::endl;
    return 1;
  }
}

}  // namespace pf2
