#include "pf2/io/tum_sequence.h"

#include <sys/stat.h>

#include <opencv2/imgcodecs.hpp>

#include "pf2/core/error.h"
#include "pf2/io/image_file.h"
#include "pf2/io/trajectory_io.h"

namespace pf2 {

namespace {

bool fileExists(const std::string& path) {
  struct stat info;
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

std::string join(const std::string& folder, const std::string& file) {
  if (folder.empty() || (!file.empty() && file.front() == '/')) return file;
  return folder.back() == '/' ? folder + file : folder + "/" + file;
}

// The last component of a folder path, trailing slashes ignored.
std::string folderName(const std::string& folder) {
  const std::string name = folder.substr(0, folder.find_last_not_of('/') + 1);
  return name.substr(name.find_last_of('/') + 1);
}

}  // namespace

bool isBonnDynamicFolder(const std::string& folder) {
  return folderName(folder).rfind("rgbd_bonn_", 0) == 0;
}

CameraIntrinsics intrinsicsForFolder(const std::string& folder,
                                     const std::string& calibration_file) {
  if (!calibration_file.empty()) return CameraIntrinsics::load(calibration_file);
  const std::string in_folder = join(folder, "camera.txt");
  // Whatever is there under that name is read (a folder named camera.txt is an error, not absent).
  struct stat info;
  if (::stat(in_folder.c_str(), &info) == 0) return CameraIntrinsics::load(in_folder);
  // Bonn folders are published without a calibration file; their name is the only hint.
  if (isBonnDynamicFolder(folder)) return CameraIntrinsics::bonnDynamic();
  // The benchmark's folder names say which Kinect recorded them.
  const std::string base = folderName(folder);
  for (const char* tag : {"freiburg1", "fr1"}) {
    if (base.find(tag) != std::string::npos) return CameraIntrinsics::tumFreiburg1();
  }
  for (const char* tag : {"freiburg2", "fr2"}) {
    if (base.find(tag) != std::string::npos) return CameraIntrinsics::tumFreiburg2();
  }
  return CameraIntrinsics::tumFreiburg3();
}

TumSequence::TumSequence(const std::string& folder) : TumSequence(folder, Options()) {}

TumSequence::TumSequence(const std::string& folder, const Options& options)
    : folder_(folder), options_(options) {
  struct stat info;
  if (::stat(folder.c_str(), &info) != 0 || !S_ISDIR(info.st_mode)) {
    throw fileError(folder, "not a sequence folder (missing or not a directory)");
  }
  if (!(options.depth_scale > 0.0)) throw Error("depth scale must be positive");
  intrinsics_ = intrinsicsForFolder(folder, options.calibration_file);

  if (!options.associations_file.empty()) {
    rgb_list_ = depth_list_ = options.associations_file;
    pairs_ = readTumAssociations(options.associations_file);
    if (pairs_.empty()) throw fileError(options.associations_file, "no associations in file");
    return;
  }
  const std::string rgb_list = join(folder, "rgb.txt");
  const std::string depth_list = join(folder, "depth.txt");
  rgb_list_ = rgb_list;
  depth_list_ = depth_list;
  const std::vector<TumListEntry> rgb = readTumList(rgb_list);
  const std::vector<TumListEntry> depth = readTumList(depth_list);
  if (rgb.empty()) throw fileError(rgb_list, "no images listed");
  if (depth.empty()) throw fileError(depth_list, "no images listed");
  std::vector<double> rgb_stamps, depth_stamps;
  for (const auto& e : rgb) rgb_stamps.push_back(e.timestamp);
  for (const auto& e : depth) depth_stamps.push_back(e.timestamp);
  for (const auto& [i, j] : associateTimestamps(rgb_stamps, depth_stamps, options.max_time_difference)) {
    pairs_.push_back({rgb[i], depth[j]});
  }
  if (pairs_.empty()) {
    throw fileError(folder, "no rgb/depth pair within " +
                                std::to_string(options.max_time_difference) + " s (" +
                                std::to_string(rgb.size()) + " rgb, " +
                                std::to_string(depth.size()) + " depth entries)");
  }
}

Frame TumSequence::frame(size_t i) const {
  const TumAssociation& pair = pairs_.at(i);
  const std::string rgb_path = join(folder_, pair.rgb.file);
  const std::string depth_path = join(folder_, pair.depth.file);
  Frame frame;
  frame.index = static_cast<int>(i);
  frame.timestamp = pair.rgb.timestamp;
  frame.intrinsics = intrinsics_;
  const cv::Size size(intrinsics_.width, intrinsics_.height);
  // An image that cannot be read is named with the list line that named it.
  const auto read = [&](const std::string& path, int flags, const std::string& what, const std::string& list,
                        int line) {
    try {
      return readImageFile(path, flags, what, size);
    } catch (const Error& e) {
      throw Error(std::string(e.what()) + " (listed on " + list + ":" + std::to_string(line) + ")");
    }
  };
  frame.rgb = read(rgb_path, cv::IMREAD_COLOR, "colour image", rgb_list_, pair.rgb.line);
  const cv::Mat raw_depth = read(depth_path, cv::IMREAD_UNCHANGED, "depth image", depth_list_, pair.depth.line);
  if (raw_depth.type() != CV_16UC1) throw fileError(depth_path, "depth image is not 16-bit single channel");
  if (raw_depth.size() != frame.rgb.size()) {
    throw fileError(depth_path, "depth size differs from the colour image " + rgb_path);
  }
  if (raw_depth.cols != intrinsics_.width || raw_depth.rows != intrinsics_.height) {
    throw fileError(depth_path, "image is " + std::to_string(raw_depth.cols) + "x" +
                                    std::to_string(raw_depth.rows) + ", calibration says " +
                                    std::to_string(intrinsics_.width) + "x" +
                                    std::to_string(intrinsics_.height));
  }
  raw_depth.convertTo(frame.depth, CV_32F, 1.0 / options_.depth_scale);
  return frame;
}

bool TumSequence::hasGroundTruth() const { return fileExists(join(folder_, "groundtruth.txt")); }

Trajectory TumSequence::groundTruth() const {
  if (!hasGroundTruth()) return Trajectory();
  // A Bonn folder as published holds marker poses: every user of this wants camera poses.
  return readTrajectory(join(folder_, "groundtruth.txt"),
                        isBonnDynamicFolder(folder_) ? TrajectoryFormat::kBonn : TrajectoryFormat::kTum);
}

}  // namespace pf2
