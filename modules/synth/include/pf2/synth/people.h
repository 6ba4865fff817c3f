#pragma once
// The people of the synthetic sequences: each has a body shape, clothing colours and a script
// (walk between points of the free floor, turn to the new heading, stand for a while, sit down on
// a chair and get up again), generated from the seed. The gait is kinematic: hips, knees and
// ankles flex with the gait phase (phase advances with the distance walked, so feet do not skate
// much), arms swing opposite to the legs, the pelvis and spine counter-rotate, and the body is
// kept on the floor, which gives the vertical bob.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "pf2/body/body_model.h"
#include "pf2/synth/static_scene.h"

namespace pf2 {

using JointRotations = std::array<Eigen::Vector3d, kBodyJointCount>;

// Joint rotations (body frame, SMPL convention) of a walking person at gait phase `phase`
// (radians; the left leg is furthest forward at pi/2) with `amplitude` in [0, 1] (0 = standing
// still). `arm_lowering` rotates the arms down from the model's rest pose (radians).
JointRotations walkingPose(double phase, double amplitude, double arm_lowering);
// A person sitting upright on a chair, hands on the thighs.
JointRotations sittingPose(double arm_lowering);
// The angle that brings the rest-pose arms of `model` (shape `shape`) to hang down by the sides.
double armLoweringAngle(const BodyModel& model, const Eigen::VectorXd& shape);

class Crowd {
 public:
  struct Options {
    int people = 3;                        // 0 .. 5
    std::uint64_t seed = 1;                // shapes, clothes, scripts
    double duration = 10.0;                // seconds the scripts must cover
    double min_speed = 0.8;                // walking speed range, m/s
    double max_speed = 1.25;               // m/s
    double sit_probability = 0.25;         // next action: sit down (people 1 and 2 own a chair)
    double stand_probability = 0.1;        // next action: stand still for 1 to 3.5 s
    double close_pass_probability = 0.25;  // a walk ends 0.7-1.1 m in front of the camera
    double leave_view_probability = 0.2;   // a walk ends out of view at the room's sides
    double middle_probability = 0.35;      // a walk ends in the middle of the view (else anywhere)
    bool first_person_seated = true;       // person 1 sits at the desk when the sequence starts
  };

  // One posed person: the parameters (world frame) and the mesh they give.
  struct Posed {
    BodyParameters parameters;
    BodyMesh mesh;
  };

  // Throws pf2::Error when people > 5 or < 0.
  Crowd(const Options& options, const StaticScene& scene, std::shared_ptr<const BodyModel> model);

  int size() const { return static_cast<int>(people_.size()); }
  const BodyModel& model() const { return *model_; }
  // Per-vertex BGR colours of person k (shirt, trousers, skin, hair, shoes).
  const std::vector<Eigen::Vector3f>& colors(int k) const { return people_.at(k).colors; }
  // Person k (0-based; its id is k + 1) at time t seconds. Thread safe (const).
  Posed pose(int k, double t) const;

 private:
  // A piece of a person's script; see people.cpp.
  struct Segment {
    enum class Kind { kWalk, kTurn, kStand, kSitDown, kSit, kStandUp } kind = Kind::kStand;
    double t0 = 0.0, t1 = 0.0;         // seconds
    Eigen::Vector2d from, to;          // floor positions, world x y
    double yaw0 = 0.0, yaw1 = 0.0;     // headings, radians about world z (0 = +x)
    double distance0 = 0.0;            // distance walked before the segment (gait phase), metres
    int seat = -1;
  };
  struct Person {
    Eigen::VectorXd shape;
    std::vector<Eigen::Vector3f> colors;
    std::vector<Segment> script;
    double stride = 1.3;               // metres per gait cycle
    double arm_lowering = 0.0;         // radians
    double rest_pelvis_height = 0.9;   // pelvis above the soles in the rest pose, metres
    Eigen::Vector3d rest_pelvis;       // rest-pose pelvis joint, body frame
  };
  Options options_;
  std::shared_ptr<const BodyModel> model_;
  std::vector<Person> people_;
  std::vector<StaticScene::Seat> seats_;
};

}  // namespace pf2
