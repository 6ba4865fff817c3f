#pragma once
// Reading an image file the way every reader of ours does: a PNG's structure is checked first
// (signature, every chunk inside the file with a correct CRC, the size in its IHDR), so that a
// truncated or corrupt file gives one error naming it, not libpng's own complaint on stderr, and
// an absurd size is refused before anything is allocated. Other formats go to OpenCV unchecked.
#include <string>

#include <opencv2/core.hpp>

namespace pf2 {

// cv::imread(path, flags) after the checks above. `what` names the image in errors ("colour
// image"); `expected`, when not empty, is the size the image must have. Throws pf2::Error naming
// the path. Thread safe.
cv::Mat readImageFile(const std::string& path, int flags, const std::string& what, const cv::Size& expected = {});

// Writes `image` in the format of the path's extension (.png, .jpg), encoded in memory and written
// atomically (temporary file + rename), so that a full disk gives one error naming the path, not
// libpng's complaint, and never leaves half a file. Throws pf2::Error naming the path. Thread safe.
void writeImageFile(const std::string& path, const cv::Mat& image);

}  // namespace pf2
