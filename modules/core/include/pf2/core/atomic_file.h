#pragma once
// Outputs are written to a temporary name beside the target and renamed over it, so a crash never
// leaves a half-written file that looks whole.
#include <functional>
#include <ostream>
#include <string>

namespace pf2 {

// Calls write(stream) on "<path>.tmp.<pid>", flushes, checks the stream and renames to path.
// Throws pf2::Error naming the path if the file cannot be opened, written or renamed; the
// temporary file is removed on failure.
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& write);

// Renames an already written temporary file into place (for writers that need a file name, such
// as cv::imwrite). Throws pf2::Error naming both paths on failure.
void commitTemporaryFile(const std::string& temporary_path, const std::string& path);
// The temporary name writeFileAtomically uses for `path`; keeps the extension so that writers
// that choose a format by extension still work.
std::string temporaryPathFor(const std::string& path);

}  // namespace pf2
