#pragma once
// VisibleCentre: the eq. 2 centre a body gives in one camera's image, and its inverse, where a body
// of a known pose stands when its eq. 2 centre is a measured one.
//
// Eq. 2 places a person at the centre of their box, at the mean depth of their visible depth. For a
// person cut by the image border both come from the part inside the image only: the centre moves
// towards the image's inside and onto whatever part is left (an arm, a shoulder), by an amount that
// depends on how much is cut. Placing the pelvis at the centre plus a fixed offset then misses it by
// 20-30 cm. This engine projects the body's mesh vertices into the image, keeps those inside it, and
// takes the same box centre at the mean depth of the visible surface (the nearest vertex per cell
// of a coarse pixel grid); pelvisFor() moves the body until that centre is the measured one.
#include <vector>

#include <Eigen/Core>

#include "pf2/core/camera_intrinsics.h"

namespace pf2 {

class VisibleCentre {
 public:
  struct Options {
    int cell_px = 6;               // pixels: side of the visible surface's grid cells, [1, 64]
    int max_iterations = 30;       // steps of pelvisFor(), [1, 1000]
    double tolerance = 0.002;      // m: pelvisFor() stops when its step is shorter, (0, 1]
    double max_move = 1.0;         // m: pelvisFor() gives up when the pelvis moved further from its start, (0, 10]
  };

  // Throws pf2::Error for intrinsics without a positive size or focal length, or options out of range.
  VisibleCentre(const CameraIntrinsics& intrinsics, const Options& options);
  explicit VisibleCentre(const CameraIntrinsics& intrinsics) : VisibleCentre(intrinsics, Options()) {}

  // The eq. 2 centre (camera frame, m) of a body whose mesh vertices, relative to its pelvis and in
  // camera axes, are relative_c, with its pelvis at pelvis_c, and the share of those vertices
  // inside the image (in [0, 1]; when share_in_view is given). False when no vertex is in view.
  // Thread safe (const).
  bool centre(const std::vector<Eigen::Vector3d>& relative_c, const Eigen::Vector3d& pelvis_c,
              Eigen::Vector3d* centre_c, double* share_in_view = nullptr) const;

  // The pelvis (camera frame) at which centre() is target_c, searched from start_c: each step moves
  // the pelvis by what its centre still misses (one step when the whole body is in view; more when
  // part is cut, as the centre then moves less than the body). False when the body leaves the view
  // or moves further than max_move; *pelvis_c is then unchanged. Thread safe (const).
  bool pelvisFor(const std::vector<Eigen::Vector3d>& relative_c, const Eigen::Vector3d& target_c,
                 const Eigen::Vector3d& start_c, Eigen::Vector3d* pelvis_c) const;

 private:
  CameraIntrinsics intrinsics_;
  Options options_;
};

}  // namespace pf2
