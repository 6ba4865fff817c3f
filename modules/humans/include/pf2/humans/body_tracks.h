#pragma once
// Each person's body through the run, in the world (data objects), and BodyTrackAssembler, which
// builds them at the end of a run from the body fits (camera frame, BodyTrackFitter) and the
// frames each person was seen in, with the loop-corrected camera poses:
//   - a frame with a fit: the fit placed in the world by eq. 4, T_w_h = T_w_c T_c_h;
//   - a frame between two fits at most max_gap apart: their poses interpolated (rotations
//     slerped joint by joint, the pelvis moved along a cubic curve with the track's velocity at
//     both ends, velocity_span);
//   - a frame before a track's first fit or after its last, at most max_extrapolation from it:
//     that fit's body moved on with the track's velocity there, drawn towards where its eq. 2
//     centre places it (below) as that grows less certain with time (centre_sigma);
//   - any other frame: the nearest fit's pose at the person's eq. 2 centre, shifted by the offset
//     between that fit's pelvis and its own frame's centre (the centre lies on the side of the
//     body the camera sees, and high on a seated person: it is no pelvis by itself); with
//     visible_centre, moved on until the eq. 2 centre that body gives in this frame's image
//     (VisibleCentre: the part inside the image only) is the measured one, less what the fit's own
//     frame measured beside its body's modelled centre: a person cut by the image border has their
//     centre on the part still in view, and the fixed offset misses the pelvis by 20-30 cm there;
//     with hold_height, at the nearest fit's pelvis height;
//   - a person with no fit at all: a standing body (arms down) placed by eq. 4 at the eq. 2 centre.
// A fit far from where the track's other fits lie relative to their eq. 2 centres is dropped first
// (max_offset_deviation; with visible_centre, a fit of a body cut by the image border is judged by
// how far its frame's centre lies from the one its body gives there, against the track's other
// fits), unless it lies on the path of the fits kept around it across a gap longer than max_gap
// (max_path_deviation); then a fit off the line between its neighbours (max_path_deviation). Every
// body of a track gets the track's shape (the mean of its fits). The joints' rotations are then
// smoothed over time (Gaussian, pose_smoothing_sigma), then the pelvis positions
// (smoothing_sigma), each body moved with its pelvis.
#include <array>
#include <map>
#include <vector>

#include <Eigen/Geometry>

#include "pf2/body/body_model.h"
#include "pf2/humans/body_track_fitter.h"
#include "pf2/humans/human_track.h"
#include "pf2/humans/visible_centre.h"

namespace pf2 {

// A person seen in one frame: their eq. 2 centre in the camera frame and the frame's keyframe anchor.
struct PersonSighting {
  int track_id = 0;
  int frame_index = 0;
  double timestamp = 0;
  int keyframe_id = -1;
  Eigen::Isometry3d T_k_c = Eigen::Isometry3d::Identity();
  Eigen::Vector3d p_c = Eigen::Vector3d::Zero();
};

struct BodyTrackFrame {
  double timestamp = 0;
  bool fitted = false;  // a fit of this very frame (else interpolated or placed by eq. 4)
  // The body's root frame in the world: the root joint's rotation, origin at the pelvis. Rotation
  // of T_w_h = rotation of body_w.pose[0].
  Eigen::Isometry3d T_w_h = Eigen::Isometry3d::Identity();
  // World-frame parameters: BodyModel::evaluate(body_w) is the person's mesh in the world.
  BodyParameters body_w;
  std::array<Eigen::Vector3d, kBodyJointCount> joints_w;
  Eigen::Vector3d pelvis_w = Eigen::Vector3d::Zero();  // = joints_w[0] = T_w_h.translation()
};

struct BodyTrack {
  int id = 0;
  Eigen::VectorXd shape;               // the track's shape coefficients
  int fits = 0;                        // frames with a fit of their own
  std::vector<BodyTrackFrame> frames;  // every frame the person was seen in, by time
};

class BodyTrackAssembler {
 public:
  struct Options {
    // s: fits further apart are not interpolated between, [0, 60]. A person out of view or hidden
    // for a second or more (no fit) is still walking the same way: interpolating across gaps up to
    // 2 s beat placing them by their eq. 2 centre, which lies on the sliver of a person still in
    // view (pf2_slam, repeatable runs, track RMSE summed over nine pf2_synth sequences 54.7 ->
    // 52.2 cm with 2 s, 53.4 with 1.5, 51.2 with 3, 54.0 with 4; held-out six 40.5 -> 39.7 with 2
    // or 3). 2 s: a walking person turns within a few seconds.
    double max_gap = 2.0;
    // s: between two fits the pelvis follows a cubic (Hermite) curve whose velocity at each end is
    // that of the fits this far beyond it (their chord if there is none within max_gap), not the
    // straight line: a person walks curves, and across a gap of a second the chord cuts them by
    // 10-20 cm. [0, 10]; 0 = the straight line. (pf2_slam, repeatable runs, track RMSE summed over
    // nine pf2_synth sequences 54.2 -> 52.4 cm, six held-out 39.1 -> 38.7 with 0.5 s; spans of
    // 0.3-0.8 s gave 52.0-52.8, BENCHMARKS "Bodies in the map".)
    double velocity_span = 0.5;
    // s: a frame this close before a track's first fit or after its last one takes that fit's
    // body moved on with the track's velocity there (velocity_span), not placed by its eq. 2
    // centre, which lies on the part of a person still in view as they enter or leave it or step
    // behind another. [0, 10]; 0 = off. (pf2_slam, repeatable runs, track RMSE summed over nine
    // pf2_synth sequences 52.4 -> 50.6 cm with 0.5 s, 50.8 with 0.3, 50.4 with 0.6; six held-out
    // 38.7 -> 37.2 with 0.5 s or 0.3.)
    double max_extrapolation = 0.5;
    // m: the spread (one standard deviation) of where a frame's eq. 2 centre places the pelvis
    // (with the nearest fit's offset or view, as for frames far from any fit). A frame placed by
    // max_extrapolation is drawn towards that place by the share of the two variances: the
    // extrapolation's grows as 1/2 extrapolation_acceleration t^2 with the time t since the fit, as
    // the person may change pace (a seated person standing up and walking off right after their
    // last fit stayed behind by 0.4 m, pf2_synth static seed 11). A centre further off than three
    // standard deviations of both is not believed (a sliver in view). [0, 1]; 0 = the extrapolation
    // alone. (135 repeatable runs of seeds 1-45, docs/BENCHMARKS.md "Bodies in the map".)
    double centre_sigma = 0.1;
    double extrapolation_acceleration = 2.0;  // m/s^2, [0, 20]: see centre_sigma
    double smoothing_sigma = 0.1;  // s: Gaussian smoothing of the pelvis over time (0 = none), [0, 5]
    // s: Gaussian smoothing of every joint's rotation over time (0 = none), [0, 5]. The fits
    // jitter with MoveNet's keypoints from one to the next, and a body moves smoothly (pf2_slam,
    // repeatable runs, MPJPE sums over nine pf2_synth sequences 826 -> 794 mm, better on each;
    // six held-out ones 597 -> 576 mm; 0.15: 793, 0.2: 799).
    double pose_smoothing_sigma = 0.1;
    // A fit whose pelvis lies further than this from where the track's other fits put it relative
    // to the eq. 2 centre (the median offset of its fits) is dropped as a wrong fit (a person
    // partly hidden by another, keypoints of two people mixed). [0.01, 10] m
    double max_offset_deviation = 0.25;
    // A fit whose pelvis lies further than this from the straight line between the fits before and
    // after it (at most a second apart, and no further apart than a brisk walk takes a person) is
    // dropped as a wrong fit: a pelvis does not leave its path by decimetres and come back within a
    // fraction of a second, while a fit of the wrong pixels (a person seated at the border as
    // another walks in) does. [0, 10] m, 0 = off. (pf2_slam, repeatable runs, track RMSE summed
    // over 15 pf2_synth sequences each: seeds 16-20 88.0 -> 76.4 cm with 0.25 m, 77.9 with 0.15,
    // seeds 1-5 64.0 -> 64.0 / 63.8; held out, seeds 26-30 88.4 -> 82.9, seeds 41-45 71.7 -> 68.2.)
    // The same distance spares a fit that max_offset_deviation would drop when it lies that close
    // to the line between the nearest fits before and after it that that rule keeps, and those lie
    // more than max_gap apart: then its frame's eq. 2 centre is wrong, not the fit (a seated
    // person's mask joined by someone passing in front), and the frames between would follow it.
    // (135 repeatable runs of seeds 1-45: 12 better, none worse, track RMSE sum 633.8 -> 617.3 cm.)
    double max_path_deviation = 0.25;
    // Frames beyond max_gap from any fit place the nearest fit's body by the eq. 2 centre it would
    // give in the image (true) or by the centre plus the fit's offset (false); with true, a fit of
    // a body cut by the image border is judged by max_offset_deviation on how far its frame's
    // centre lies from the one its body gives there (its offset is no guide).
    bool visible_centre = true;
    // s: with visible_centre, a fit of a body cut by the image border is judged against the view
    // biases of the fits within this time of it (at least three), not against all of the track's,
    // [0, 60]; 0 = all. How far the measured eq. 2 centre lies from the body's changes with what
    // the person's pixels hold around them: a seated person's centre lay 0.29 m deeper than their
    // body's (the chair and the wall behind them in their box and mask), and when they walked up to
    // the camera, cut by the border, their right fits (centre and body agreeing) were all dropped
    // for lying that far from the track's median (pf2_synth static seed 29: 90 frames placed 16 cm
    // nearer the camera than the person; 135 repeatable runs: 8 better, 3 worse, docs/BENCHMARKS.md).
    // Whole bodies keep the track's median offset: judged by the fits around them, a second of
    // wrong fits (a seated person's keypoints mixed with a walker's) vouched for each other.
    double cut_bias_window = 1.0;
    // Frames beyond max_gap from any fit keep the nearest fit's pelvis height (along the world's
    // up, when assemble() is given it) and take only the horizontal position from the eq. 2 centre
    // (true), or the centre's height too (false). A person's pelvis keeps its height while they
    // walk, and the centre's height is its weakest part: it follows whatever is in view (a person
    // behind a table or cut by the bottom border, another person's pixels in the mask), and a close
    // person cut by the border moves it by decimetres (pf2_slam, repeatable runs, track RMSE summed
    // over 30 pf2_synth sequences 142.4 -> 138.7 cm, none worse by more than 1 mm; 15 held-out
    // ones 87.2 -> 87.3 cm).
    bool hold_height = true;
  };

  // The model must outlive the assembler.
  BodyTrackAssembler(const BodyModel& model, const Options& options) : model_(model), options_(options) {}

  // sightings: every frame each person was seen in (with a pose); fits: BodyTrackFitter::finish();
  // keyframe_poses: the final T_w_k of every keyframe; intrinsics: the frames' camera; up_w: the
  // world's up (UpDirectionEstimator; normalised here), zero when unknown (then no height is held,
  // Options::hold_height). Tracks in id order. Thread safe (const).
  std::vector<BodyTrack> assemble(const std::vector<PersonSighting>& sightings, const std::vector<BodyTrackFit>& fits,
                                  const std::map<int, Eigen::Isometry3d>& keyframe_poses,
                                  const CameraIntrinsics& intrinsics,
                                  const Eigen::Vector3d& up_w = Eigen::Vector3d::Zero()) const;

 private:
  // A fit as its own frame's image shows it (Options::visible_centre): the share of its mesh inside
  // the image, and how far the eq. 2 centre measured in that frame lies from the one its body gives
  // there (VisibleCentre), in that camera's axes.
  struct FitView {
    bool valid = false;  // false: the body is out of its own frame's view (or the frame unknown)
    double share_in_view = 0;
    Eigen::Vector3d bias_c = Eigen::Vector3d::Zero();
  };
  BodyTrack assembleTrack(int id, const std::vector<const PersonSighting*>& seen,
                          std::vector<const BodyTrackFit*> fitted,
                          const std::map<int, Eigen::Isometry3d>& keyframe_poses,
                          const CameraIntrinsics& intrinsics, const Eigen::Vector3d& up_w) const;
  // extrapolated_w (since seconds from its fit) drawn towards by_centre_w (Options::centre_sigma).
  Eigen::Vector3d extrapolatedTowardsCentre(const Eigen::Vector3d& extrapolated_w, const Eigen::Vector3d& by_centre_w,
                                            double since) const;
  // The pelvis's velocity at fit `end`, from it to the first fit at least velocity_span beyond it
  // in step's direction (+1 later, -1 earlier); false when there is none within max_gap.
  bool trackVelocity(const std::vector<const BodyTrackFit*>& fitted, const std::vector<BodyParameters>& bodies,
                     size_t end, int step, Eigen::Vector3d* velocity) const;
  // The pelvis between fits a and a + 1 at x in [0, 1] of the way (Options::velocity_span).
  Eigen::Vector3d translationBetweenFits(const std::vector<const BodyTrackFit*>& fitted,
                                         const std::vector<BodyParameters>& bodies, size_t a, double x) const;
  // The median view bias a cut fit i is judged against (Options::cut_bias_window).
  Eigen::Vector3d nearbyBias(const std::vector<FitView>& views, const std::vector<const BodyTrackFit*>& fitted,
                             size_t i, const Eigen::Vector3d& track_median) const;
  void dropOutlierFits(std::vector<BodyParameters>* bodies, std::vector<Eigen::Vector3d>* offsets,
                       std::vector<const BodyTrackFit*>* fitted, std::vector<FitView>* views) const;
  // Sets `keep` again for the fits it drops that lie on the path of the fits it keeps.
  void spareFitsOnPath(const std::vector<BodyParameters>& bodies, const std::vector<const BodyTrackFit*>& fitted,
                       std::vector<bool>* keep) const;
  // Options::max_path_deviation, the worst fit first, until no fit is that far off its neighbours' line.
  void dropFitsOffPath(std::vector<BodyParameters>* bodies, std::vector<Eigen::Vector3d>* offsets,
                       std::vector<const BodyTrackFit*>* fitted, std::vector<FitView>* views) const;
  FitView fitView(const BodyParameters& body_w, const Eigen::Vector3d& rest_pelvis, const PersonSighting& own,
                  const Eigen::Isometry3d& T_w_c, const VisibleCentre& image) const;
  // Every few vertices of the body's mesh, minus its pelvis (world axes).
  std::vector<Eigen::Vector3d> verticesAboutPelvis(const BodyParameters& body_w,
                                                   const Eigen::Vector3d& rest_pelvis) const;
  // The pelvis (world) at which the fit's body (relative_w: verticesAboutPelvis) gives sighting s's
  // eq. 2 centre, less the view's bias, searched from start_w; false (and *pelvis_w unchanged) when
  // that fails.
  bool pelvisByVisibleCentre(const PersonSighting& s, const Eigen::Isometry3d& T_w_c, const FitView& view,
                             const std::vector<Eigen::Vector3d>& relative_w, const Eigen::Vector3d& start_w,
                             const VisibleCentre& image, Eigen::Vector3d* pelvis_w) const;
  BodyParameters fitInWorld(const BodyTrackFit& fit, const Eigen::VectorXd& shape,
                            const std::map<int, Eigen::Isometry3d>& keyframe_poses) const;
  BodyTrackFrame frameFromBody(double timestamp, bool fitted, const BodyParameters& body_w) const;
  void smoothPose(BodyTrack* track) const;
  void smoothPelvis(BodyTrack* track) const;

  const BodyModel& model_;
  Options options_;
};

// The person tracks of humans.txt from the bodies: each frame's pelvis.
std::vector<HumanTrack> pelvisTracks(const std::vector<BodyTrack>& bodies);

// Interpolates two bodies of the same shape: each joint's rotation slerped, the pelvis (with the
// root translation) moved linearly; t in [0, 1]. Thread safe.
BodyParameters interpolateBodies(const BodyParameters& a, const BodyParameters& b, double t);

}  // namespace pf2
