#pragma once
// A synthetic dynamic RGB-D sequence with complete ground truth: the static room of StaticScene,
// people from the body model walking, standing and sitting in it, a TUM-like camera motion, a
// Kinect-like depth sensor. Frames are rendered on demand (in memory, for the pipeline and tests)
// or written as a TUM folder plus gt/ (see docs/synth.md for the layout).
//
//   SyntheticSequence::Options options;  options.people = 2;  options.frames = 60;
//   SyntheticSequence sequence(options);
//   FrameGroundTruth truth;
//   Frame frame = sequence.frame(10, &truth);   // truth.T_w_c, truth.labels, truth.people
//   sequence.writeTumFolder("out/synthetic");
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "pf2/body/body_model.h"
#include "pf2/core/camera_intrinsics.h"
#include "pf2/core/frame.h"
#include "pf2/core/frame_source.h"
#include "pf2/synth/camera_motion.h"
#include "pf2/synth/depth_sensor_model.h"
#include "pf2/synth/people.h"
#include "pf2/synth/rasterizer.h"
#include "pf2/synth/static_scene.h"

namespace pf2 {

// One person in one frame, world frame of the sequence.
struct PersonGroundTruth {
  int id = 0;                          // label value in the label image, >= 1, stable
  BodyParameters body;                 // root rotation includes the world orientation
  std::array<Eigen::Vector3d, kBodyJointCount> joints_w;  // posed joints, SMPL order
  Eigen::Vector3d pelvis_w = Eigen::Vector3d::Zero();     // = joints_w[0]
  int visible_pixels = 0;              // pixels with this id in the label image
  cv::Rect box;                        // tight box of those pixels (empty when none)
  double visible_fraction = 0.0;       // visible_pixels / pixels covered with no occluder, no border
};

struct FrameGroundTruth {
  double timestamp = 0.0;
  Eigen::Isometry3d T_w_c = Eigen::Isometry3d::Identity();
  cv::Mat labels;       // CV_16U, 0 static, k person k; aligned with the colour image
  cv::Mat exact_depth;  // CV_32F metres, the rendered depth before the sensor model (0 = nothing)
  std::vector<PersonGroundTruth> people;  // everyone in the scene, visible or not, by id
};

class SyntheticSequence : public FrameSource {
 public:
  struct Options {
    int frames = 300;                       // number of frames
    double fps = 30.0;                      // frame rate, Hz
    double start_time = 1700000000.0;       // timestamp of frame 0, seconds
    std::uint64_t seed = 1;                 // scene textures, people, noise
    int people = 3;                         // 0 .. 5
    CameraMotion camera = CameraMotion::kXyz;
    CameraIntrinsics intrinsics = CameraIntrinsics::tumFreiburg3();
    bool close_people = false;              // people cross 0.7-1.6 m in front of the camera one after
                                            // the other, entering and leaving at the image's sides
                                            // (pf2_synth --close); distances and pauses: crowd.close
    bool motion_blur = false;               // colour blurred along the image motion, depth mixed at edges
    double exposure = 1.0 / 30.0;           // exposure time for the blur, seconds (<= 1 / fps)
    double texels_per_metre = 128;          // scene texture resolution
    DepthSensorModel::Options sensor;       // noise on/off, range, misalignment
    Rasterizer::Options rasterizer;         // lighting, threads
    Crowd::Options crowd;                   // walking speeds, how often people sit, stand, pass close;
                                            // its people, seed, duration and close.enabled come from
                                            // the fields above
  };

  // Builds the scene and the people's scripts. Throws pf2::Error on invalid options (and when
  // people are asked for but the body model cannot be loaded).
  explicit SyntheticSequence(const Options& options);
  ~SyntheticSequence() override;

  const Options& options() const { return options_; }
  size_t size() const override { return static_cast<size_t>(options_.frames); }
  std::string description() const override;
  double timestamp(size_t i) const;
  // Ground-truth camera pose of frame i (T_w_c). Thread safe.
  Eigen::Isometry3d pose(size_t i) const;

  // Renders frame i. Thread safe (const; frames may be rendered concurrently).
  Frame frame(size_t i) const override;
  Frame frame(size_t i, FrameGroundTruth* truth) const;

  // The posed body meshes of frame i, world frame, in id order (id = index + 1). Thread safe.
  std::vector<BodyMesh> bodies(size_t i) const;

  const StaticScene& scene() const { return *scene_; }

  // Writes the TUM folder (rgb/, depth/, rgb.txt, depth.txt, groundtruth.txt, camera.txt) and gt/
  // into out_dir (created if needed). Every file is written atomically. `progress` (optional) is
  // called after each frame with the number of frames done. Throws pf2::Error naming the file.
  // Thread safe (const), but two calls must not write the same folder.
  void writeTumFolder(const std::string& out_dir,
                      const std::function<void(size_t)>& progress = nullptr) const;

 private:
  Options options_;
  std::shared_ptr<const StaticScene> scene_;
  std::unique_ptr<Crowd> crowd_;
  Rasterizer rasterizer_;
  DepthSensorModel sensor_;
};

}  // namespace pf2
