#pragma once
// Pinhole intrinsics of the depth-registered colour camera.
#include <string>

#include <Eigen/Core>

namespace pf2 {

struct CameraIntrinsics {
  double fx = 535.4;  // focal length x, pixels
  double fy = 539.2;  // focal length y, pixels
  double cx = 320.1;  // principal point x, pixels
  double cy = 247.6;  // principal point y, pixels
  int width = 640;    // image width, pixels
  int height = 480;   // image height, pixels

  // TUM RGB-D benchmark presets (the benchmark's published values, 640x480).
  static CameraIntrinsics tumFreiburg1();
  static CameraIntrinsics tumFreiburg2();
  static CameraIntrinsics tumFreiburg3();
  // Bonn RGB-D Dynamic Dataset (Palazzolo et al., IROS 2019), the dataset's published values,
  // 640x480; its folders ship no calibration file.
  static CameraIntrinsics bonnDynamic();
  // "fr1" | "fr2" | "fr3" | "bonn"; throws pf2::Error naming the unknown preset and the allowed ones.
  static CameraIntrinsics preset(const std::string& name);

  // Calibration file: "key value" lines (fx fy cx cy width height), '#' comments.
  // All six keys are required; throws pf2::Error with file and line on any problem.
  static CameraIntrinsics load(const std::string& path);
  // Writes the same format atomically.
  void save(const std::string& path) const;

  // Pixel (u, v) with depth z (metres) to a point in the camera frame.
  Eigen::Vector3d backProject(double u, double v, double z) const {
    return {(u - cx) * z / fx, (v - cy) * z / fy, z};
  }
  // Camera-frame point to pixel coordinates (z must be > 0).
  Eigen::Vector2d project(const Eigen::Vector3d& p_c) const {
    return {fx * p_c.x() / p_c.z() + cx, fy * p_c.y() / p_c.z() + cy};
  }
  // Scales focal lengths and principal point for an image resized by `factor`.
  CameraIntrinsics scaled(double factor) const;
};

}  // namespace pf2
