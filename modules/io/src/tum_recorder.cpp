#include "pf2/io/tum_recorder.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

#include <opencv2/imgcodecs.hpp>

#include "pf2/core/error.h"
#include "pf2/io/image_file.h"

namespace pf2 {

namespace {

constexpr double kDepthUnitsPerMetre = 5000.0;  // TUM's depth scale

}  // namespace

TumRecorder::TumRecorder(const std::string& folder) : folder_(folder) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::exists(folder, error) && !(fs::is_directory(folder, error) && fs::is_empty(folder, error))) {
    throw fileError(folder, "the recording folder exists and is not empty");
  }
  fs::create_directory(folder, error);
  fs::create_directory(folder + "/rgb", error);
  fs::create_directory(folder + "/depth", error);
  if (!fs::is_directory(folder + "/depth")) throw fileError(folder, "cannot create the recording folder");
  rgb_list_.open(folder + "/rgb.txt");
  depth_list_.open(folder + "/depth.txt");
  if (!rgb_list_ || !depth_list_) throw fileError(folder, "cannot write the recording's lists");
  rgb_list_ << "# colour images recorded by pf2_slam\n# timestamp filename\n";
  depth_list_ << "# depth images recorded by pf2_slam (16-bit PNG, 5000 units per metre)\n# timestamp filename\n";
}

void TumRecorder::add(const Frame& frame) {
  if (frames_ == 0) frame.intrinsics.save(folder_ + "/camera.txt");
  char stamp[32];
  std::snprintf(stamp, sizeof(stamp), "%.6f", frame.timestamp);
  const std::string rgb = std::string("rgb/") + stamp + ".png", depth = std::string("depth/") + stamp + ".png";
  cv::Mat depth_units;
  frame.depth.convertTo(depth_units, CV_16U, kDepthUnitsPerMetre);
  writeImageFile(folder_ + "/" + rgb, frame.rgb);
  writeImageFile(folder_ + "/" + depth, depth_units);
  rgb_list_ << stamp << ' ' << rgb << '\n' << std::flush;
  depth_list_ << stamp << ' ' << depth << '\n' << std::flush;
  if (!rgb_list_ || !depth_list_) throw fileError(folder_, "cannot write the recording's lists");
  ++frames_;
}

}  // namespace pf2
