#pragma once
// The people of the synthetic sequences: each has a body shape, clothing colours and a script
// (walk between points of the free floor, turn to the new heading, stand for a while, sit down on
// a chair and get up again), generated from the seed. People keep out of each other's way: each
// action of a person's script keeps clear of the people whose scripts were written before. The
// gait is kinematic: hips, knees and ankles flex with the gait phase (phase advances with the
// distance walked, so feet do not skate much), arms swing opposite to the legs, the pelvis and
// spine counter-rotate, and the body is kept on the floor, which gives the vertical bob.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "pf2/body/body_model.h"
#include "pf2/synth/static_scene.h"

namespace pf2 {

namespace synth {
class HashRng;
}

using JointRotations = std::array<Eigen::Vector3d, kBodyJointCount>;

// Joint rotations (body frame, SMPL convention) of a walking person at gait phase `phase`
// (radians; the left leg is furthest forward at pi/2) with `amplitude` in [0, 1] (0 = standing
// still). `arm_lowering` rotates the arms down from the model's rest pose (radians).
JointRotations walkingPose(double phase, double amplitude, double arm_lowering);
// A person sitting upright on a chair, hands on the thighs.
JointRotations sittingPose(double arm_lowering);
// The angle that brings the rest-pose arms of `model` (shape `shape`) to hang down by the sides.
double armLoweringAngle(const BodyModel& model, const Eigen::VectorXd& shape);
// A posed body as the rasteriser draws it: the mesh's vertices and triangles, its normals, one
// colour per vertex (BGR in [0, 1]) and the label its pixels get.
RenderMesh bodyRenderMesh(const BodyMesh& mesh, std::vector<Eigen::Vector3f> colors, std::uint16_t label);

class Crowd {
 public:
  // Close crossings: people walk across the camera's view close in front of it, one after the
  // other, from beyond one side edge of the view to beyond the other, so that a person covers a
  // large part of the image and is cut by the border while the room stays visible behind. A
  // crossing is a V with its tip on the view's axis: towards the camera, a turn, away again (a
  // straight line when not bent). Planned against the camera path given to the constructor.
  // Away from their crossings people keep out of view or at least max_distance away.
  struct CloseCrossings {
    bool enabled = false;
    double min_distance = 0.7;    // floor distance from the camera centre to a crossing's tip (the
    double max_distance = 1.6;    // person's axis), metres; 0.3 <= min <= max <= 3
    double max_bend = 0.5;        // angle of each half of the V to the image plane, radians, 0 .. 0.8
    double look_probability = 0.4;  // a crosser stops at the tip and faces the camera, 0 .. 1
    double look_time = 0.8;       // for this long, seconds, 0 .. 5
    double min_pause = 0.0;       // seconds from one person leaving the view to the next entering
    double max_pause = 1.0;       // it, 0 <= min_pause <= max_pause
  };

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
    double min_separation = 0.6;           // floor distance people keep between their pelvises, metres,
                                           // 0 .. 2 (0: they may walk through each other, as before);
                                           // close crossings and the walks to them are not kept apart
    CloseCrossings close;                  // when enabled, walks between crossings never end close
                                           // in front of the camera (close_pass_probability unused)
  };

  // Where the camera is over time: what close crossings are planned against.
  struct CameraPath {
    std::function<Eigen::Isometry3d(double)> pose_at;  // T_w_c at t seconds
    double half_view_tan = 0.6;  // tan of half the horizontal field of view (wider side), > 0
  };

  // One posed person: the parameters (world frame) and the mesh they give.
  struct Posed {
    BodyParameters parameters;
    BodyMesh mesh;
  };

  // Throws pf2::Error when people > 5 or < 0, min_separation is outside 0 .. 2, on invalid
  // close-crossing settings, and when close crossings are enabled without camera.pose_at.
  Crowd(const Options& options, const StaticScene& scene, std::shared_ptr<const BodyModel> model,
        const CameraPath& camera);
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
  class ScriptWriter;   // one person's script as it is written; people.cpp
  class ScriptPlanner;  // writes every script, close crossings included; people.cpp
  struct PlannedCrossing;

  struct Person {
    Eigen::VectorXd shape;
    std::vector<Eigen::Vector3f> colors;
    std::vector<Segment> script;
    double speed = 1.0;                // walking speed, m/s
    double stride = 1.3;               // metres per gait cycle
    double arm_lowering = 0.0;         // radians
    double rest_pelvis_height = 0.9;   // pelvis above the soles in the rest pose, metres
    Eigen::Vector3d rest_pelvis;       // rest-pose pelvis joint, body frame
  };
  // Shape, clothes and walking speed of a person, drawn from `rng`.
  static Person makePerson(const BodyModel& model, const Options& options, synth::HashRng* rng);
  Options options_;
  std::shared_ptr<const BodyModel> model_;
  std::vector<Person> people_;
  std::vector<StaticScene::Seat> seats_;
};

}  // namespace pf2
