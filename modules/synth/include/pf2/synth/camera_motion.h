#pragma once
// Camera trajectories of the synthetic sequences, modelled on the TUM RGB-D benchmark's
// fr3/walking_* and fr1 motions. All look into the room of StaticScene from its y = 0 side;
// poses are T_w_c in the scene's world frame (z up, metres).
#include <string>

#include <Eigen/Geometry>

namespace pf2 {

enum class CameraMotion {
  kStatic,      // a tripod-like camera: a few millimetres of sway only
  kXyz,         // +-0.25 m translations along the camera's x, then y, then z axis (4 s each)
  kHalfsphere,  // moves on a 0.5 m radius half sphere, always looking at the desk
  kRpy,         // rotations about the camera's own axes (roll, pitch, yaw; +-20 degrees) in place
  kLoop,        // walks an ellipse (3 x 0.6 m) in front of the room and returns to its start
  kAbove,       // mounted high (2.4 m, a robot's mast or a wall bracket), looking down 38-45
                // degrees at the floor while it pans and drifts slowly: people seen from above
};

// "static" | "xyz" | "halfsphere" | "rpy" | "loop" | "above"; throws pf2::Error on anything else.
CameraMotion cameraMotionFromName(const std::string& name);
const char* cameraMotionName(CameraMotion motion);

// Pose at time t seconds of a sequence lasting `duration` seconds (the loop closes at
// max(duration, 10 s)). Smooth in t. Thread safe.
Eigen::Isometry3d cameraPoseAt(CameraMotion motion, double t, double duration);

// Camera looking from position_w at target_w with the world z axis up (image y points down).
Eigen::Isometry3d lookAt(const Eigen::Vector3d& position_w, const Eigen::Vector3d& target_w);

}  // namespace pf2
