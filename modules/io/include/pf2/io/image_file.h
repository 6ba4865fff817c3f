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

}  // namespace pf2
