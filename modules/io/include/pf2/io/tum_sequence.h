#pragma once
// A TUM RGB-D sequence folder (rgb.txt, depth.txt, rgb/, depth/, optional groundtruth.txt) read
// lazily: the lists are parsed and associated on construction, images are loaded per frame.
#include <string>
#include <vector>

#include "pf2/core/frame.h"
#include "pf2/core/frame_source.h"
#include "pf2/core/pose.h"
#include "pf2/io/tum_lists.h"

namespace pf2 {

class TumSequence : public FrameSource {
 public:
  struct Options {
    // Depth PNG value per metre (TUM: 5000).
    double depth_scale = 5000.0;
    // Largest rgb/depth timestamp difference accepted when associating, seconds.
    double max_time_difference = 0.02;
    // Associations file ("rgb_stamp rgb_file depth_stamp depth_file"); empty = associate here.
    std::string associations_file;
    // Camera calibration file (CameraIntrinsics::load format); empty = "camera.txt" in the folder
    // if present, else the Bonn preset for a Bonn RGB-D Dynamic folder (isBonnDynamicFolder),
    // else the TUM preset named by the folder (freiburg1/2/3), else freiburg3.
    std::string calibration_file;
  };

  // Throws pf2::Error naming the file (and line) when a list is missing or malformed, or when no
  // rgb/depth pair can be associated.
  explicit TumSequence(const std::string& folder);
  TumSequence(const std::string& folder, const Options& options);

  size_t size() const override { return pairs_.size(); }
  std::string description() const override { return "TUM folder " + folder_; }
  const std::string& folder() const { return folder_; }
  const CameraIntrinsics& intrinsics() const { return intrinsics_; }
  // The colour image's timestamp of frame i (the frame's timestamp).
  double timestamp(size_t i) const { return pairs_.at(i).rgb.timestamp; }
  const TumAssociation& files(size_t i) const { return pairs_.at(i); }

  // Loads frame i. Throws pf2::Error naming the image when it is missing, unreadable, of the wrong
  // type (depth must be 16-bit single channel) or of a size other than the calibration's.
  // Thread safe (reads only).
  Frame frame(size_t i) const override;

  // groundtruth.txt of the folder as camera poses (a Bonn folder's marker poses converted),
  // empty when the folder has none.
  bool hasGroundTruth() const;
  Trajectory groundTruth() const;

 private:
  std::string folder_;
  std::string rgb_list_, depth_list_;  // the files that list the images (named in errors)
  Options options_;
  CameraIntrinsics intrinsics_;
  std::vector<TumAssociation> pairs_;
};

// True for a folder of the Bonn RGB-D Dynamic Dataset as published: its name starts with
// "rgbd_bonn_" (e.g. rgbd_bonn_crowd). Such a folder's groundtruth.txt holds marker poses, not
// camera poses: read it with TrajectoryFormat::kBonn (trajectory_io.h).
bool isBonnDynamicFolder(const std::string& folder);

// Picks the intrinsics as TumSequence::Options::calibration_file describes.
CameraIntrinsics intrinsicsForFolder(const std::string& folder, const std::string& calibration_file);

}  // namespace pf2
