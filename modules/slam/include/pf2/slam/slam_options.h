#pragma once
// Every knob of the pipeline in one struct made of the stages' own Options (DESIGN.md: one list
// of knobs). slamSettings() declares each setting once; docs/config.md is generated from it.
#include <string>
#include <vector>

#include "pf2/core/config_file.h"
#include "pf2/core/settings.h"
#include "pf2/detection/crop_segmenter.h"
#include "pf2/detection/detector_factory.h"
#include "pf2/detection/pose_refiner.h"
#include "pf2/filters/dual_bbox_filter.h"
#include "pf2/humans/body_track_fitter.h"
#include "pf2/humans/body_tracks.h"
#include "pf2/humans/human_tracker.h"
#include "pf2/registration/gap_interpolator.h"
#include "pf2/registration/tracker.h"
#include "pf2/registration/trajectory_smoother.h"
#include "pf2/slam/keyframe_prediction.h"
#include "pf2/slam/removal_backfill.h"
#include "pf2/slam/scene_export.h"
#include "pf2/surface/mapper.h"

namespace pf2 {

struct SlamOptions {
  // Person detector backend: a name of humanDetectorNames(), "none" (no person removal: the
  // baseline that shows what removal buys) or "auto" ("learned" when its models are installed,
  // else "hog" with a warning; "gt", the ground-truth oracle, only when asked for by name).
  std::string detector = "auto";
  // The gt backend hands over its person masks, as a segmenting detector (selfie, learned) does,
  // so the filter's mask addition runs; detector.gt_masks false gives the paper's boxes-only input.
  DetectorOptions detection = defaultDetectionOptions();
  // Frames per MoveNet run of the learned detector; handed to it as detection.extra's
  // "learned.pose_every" when the detector is made (createSlamDetector).
  int learned_pose_every = 3;
  // The learned detector's person probability, "selfie" or "rvm"; handed to it as
  // "learned.segmenter" (createSlamDetector).
  std::string learned_segmenter = "selfie";
  // "learned.crop_masks" (createSlamDetector).
  bool learned_crop_masks = false;
  // "learned.crop_size": the crop network's input side in pixels (createSlamDetector).
  int learned_crop_size = PersonCropSegmenter::Options{}.input_size;
  // "learned.candidate_poses" (createSlamDetector).
  bool learned_candidate_poses = false;
  DualBBoxFilter::Options filter = defaultFilterOptions();
  // The filter's geometric addition (filter.geometric): depth measured more than
  // geometric_margin metres in front of the static depth predicted from the newest keyframes is
  // removed as moving, whether or not a detector saw a person there. The floor plane below is used
  // with it off too: a scene prior, not a residual.
  KeyframeDepthPrediction::Options prediction;
  double geometric_margin = 0.15;  // metres, > 0
  int geometric_opening = 4;       // pixels: thinner dynamic regions are dropped (>= 0)
  double static_margin = 0.06;     // metres (plus 1 % of the depth): depth this close to the
                                   // prediction is known static (filter.keep_static)
  // metres (plus 1 % of the depth): depth this close to the floor plane (FloorEstimator, once the
  // world's up has settled) is known static too, where no keyframe has seen it: the floor beside
  // a person present since the first frame. pf2_synth hard cases, learned detector: 0.8-1.4 points
  // more of the static depth kept, 0.05-0.15 fewer of the people removed; Bonn crowd 1.42 cm
  // either way (docs/BENCHMARKS.md). 0 = off.
  double floor_margin = 0.03;
  // Person removal carried back in time (RemovalBackfill): the map and masks/ get each frame
  // `backfill.frames` frames late, with the people found in those later frames removed from it
  // too; the tracker and the live results never wait. 0 frames = off.
  RemovalBackfill::Options backfill;
  // metres, in [0, 5]; 0 = off: the depth under a posed person's mask lying more than this behind
  // their body (depthBehindBodies in person_centres.h) goes to the map and masks/, not to the
  // tracker: the selfie mask's spill onto the wall, the desk or the chair behind them. pf2_synth,
  // learned detector: 0.1-1.1 points more of the static depth kept, up to 0.2 fewer of the
  // people removed (docs/BENCHMARKS.md).
  double behind_body_margin = 0.5;
  Tracker::Options tracker;
  // trajectory.txt's positions smoothed over time at the end of the run (TrajectorySmoother);
  // the map, the people and the live poses use the poses as measured.
  TrajectorySmoother::Options trajectory;
  // Frames tracking could not measure (bridged or lost) between two measured ones get poses
  // interpolated between them at the end of the run, before the smoothing (GapInterpolator).
  GapInterpolator::Options gaps;
  // Human trajectories (paper eq. 2-3): each filtered person's centre in the world frame of
  // trajectory.txt, associated into tracks and written to humans.txt (needs a detector).
  bool track_humans = true;
  // For a person detected with a mask: d_m of eq. 2 over their depths inside their principal
  // interval (h_min, h_max) widened by the filter's human_margin only (the dilated mask also takes
  // the edges of people in front or behind); false: over all of D_h^t, as the paper writes it.
  bool human_depth_in_interval = true;
  // For a person detected with a mask and keypoints: d_m over their depths within this many metres
  // of the median depth under their confident keypoints (the filter's joint_min_count and
  // joint_min_score), when at least human_joint_min_share of the depths d_m would use lie there,
  // and their body fit sees only those depths. A mask that merged two people holds depths of both
  // in one interval; the keypoints are one body's. 0 = off (d_m over the interval's depths, the
  // fit over all of D_h^t).
  double human_joint_band = 0.3;
  double human_joint_min_share = 0.2;
  // For a person without such a band: when their depths d_m would use fall into groups parted by
  // at least human_group_gap metres with (next to) no depth between them, and the groups other
  // than the largest hold at least human_group_min_share of them, d_m, the box and the body fit
  // use the largest group only. A segmentation that merged a person with someone entering in front
  // of them, whose pose it has not found, put the centre between the two (pf2_synth halfsphere
  // seed 2: the track of a standing person moved onto the walker). 0 = off.
  double human_group_gap = 0.3;
  double human_group_min_share = 0.1;
  // Eq. 2's box for a person's centre: the box of the depths d_m rests on, each side moved in past
  // human_box_trim of them (a few stray pixels at the person's depth do not stretch it), instead
  // of the detector's box. A false mask component the detector joined to a person stretches their
  // box, up to the whole image's width (pf2_synth seed 9: a person's box 0-640 px put their centre
  // 0.66 m beside them, and their track took turns with a second one). false = the detector's box.
  bool human_box_from_depths = true;
  double human_box_trim = 0.02;
  // A person with keypoints more than this share of whose depths D_h^t lie outside the region
  // their body may fill (from their confident keypoints, the filter's joint_min_score and
  // joint_min_count; ownParts in person_centres.h), and behind them, is placed, described and
  // fitted with only the depths inside it: the segmenter painted the wall beside them and their
  // one pose took the whole component. Removal still takes all of it. 1 = never.
  double human_max_outside_pose = 0.7;
  // A person whose d_m rests on fewer depths than this fraction of the image's pixels gets no
  // centre: a sliver of a person at the image border or behind another gives a box centre far
  // from the body and a depth histogram that may be the other person's (0 = every person).
  double human_min_area = 0.001;
  // Metres: of two centres of one frame this near each other (camera frame), the one resting on
  // fewer depths is dropped: one body seen as two people (a person behind another whose depths
  // are the near one's). People do not stand with their centres this close. 0 = keep every centre.
  // (pf2_slam, repeatable runs of pf2_synth seeds 1-5: identity switches 10 -> 7, tracks 47 -> 46
  // for 45 people; 0.3, 0.4 and 0.5 m alike.)
  double human_same_body = 0.3;
  // A track seen in fewer frames is left out of humans.txt and humans.json: a detection that
  // lasts a third of a second is a false one far more often than a person.
  int human_min_frames = 10;
  HumanTracker::Options humans;
  // Bodies (paper §III-C, eq. 4): each tracked person's body model fitted to their keypoints and
  // depth in a thread of its own, placed in the world with the final poses; the tracks of
  // humans.txt then follow the fitted pelvis. Needs a detector with keypoints (learned, movenet);
  // without keypoints every body is a standing one at the eq. 2 centre.
  bool fit_bodies = true;
  // A person whose confident keypoints (filter.joint_min_score) lie on their own depth D_h^t less
  // often than this share gets no body fit that frame: the pose is another person's (a merged
  // mask whose one pose is the person behind), and a fit of it at this person's depth lands
  // between the two. In [0, 1], 0 = every person is fitted.
  double body_min_keypoints_on_person = 0.5;
  BodyTrackFitter::Options bodies;
  // Before each fit, MoveNet looks again at a crop around the person (PoseRefiner): the
  // whole-frame pass sees a person 3-4 m away at 40-60 network pixels. Only with the detectors
  // whose keypoints are MoveNet's (learned, movenet).
  bool refine_keypoints = true;
  PoseRefiner::Options keypoint_refiner;
  BodyTrackAssembler::Options body_tracks;
  SceneOptions scene;                // scene.ply / scene.obj: the map with the bodies and tracks
  // Bounded memory on long runs: the newest 300 keyframes stay re-integrable (about 100 MB of
  // stored images), TSDF blocks farther than 10 m from the camera are dropped (a room is never
  // cut; a long corridor is).
  Mapper::Options mapper = defaultMapperOptions();
  bool build_map = true;             // fuse keyframes into the TSDF and OctoMap
  bool synchronous_map = false;      // fuse in the front end's thread: the same map on every run
                                     // (with tracker.asynchronous_backend false), slower
  bool follow_corrections = false;   // re-fuse moved keyframes after every pose-graph correction, not
                                     // only at the end (the same final map; for a reader during the run)
  int fuse_every = 10;               // also fuse every n-th tracked frame between keyframes (0 = keyframes only):
                                     // surface seen only briefly (behind people who walk by) gets into the map
  Mapper::ExportOptions map_files;   // which map files are written at the end
  bool write_masks = false;          // masks/<timestamp>.png per frame: 8-bit, 255 = depth the
                                     // filter removed (people and what it took with them)
  int max_frames = 0;                // frames processed from the start (0 = all)
  int prefetch_frames = 4;           // frames decoded ahead in a loader thread
  bool progress = true;              // progress line with fps on standard error
  // Threads OpenCV's own parallel loops (DNN inference, resizing, ...) may use; 0 = OpenCV's
  // default (every core). The pipeline already runs its stages in threads of their own.
  int opencv_threads = 0;

  // The filter as the pipeline runs it: the paper's Algorithm 1 plus the backend mask, the
  // temporal guard and the geometric addition fed by the keyframes' prediction (docs/BENCHMARKS.md).
  static DualBBoxFilter::Options defaultFilterOptions();
  static DetectorOptions defaultDetectionOptions();
  static Mapper::Options defaultMapperOptions();
};

// Every setting of SlamOptions, declared once with its key, unit, range and meaning (the list is
// docs/config.md, generated from it): bound to *options, which must outlive the result.
Settings slamSettings(SlamOptions* options);

// A named set of settings (pf2_slam --preset NAME): what a kind of use changes from the
// defaults, applied before --config and --set, so either can still change any of them.
struct SlamPreset {
  std::string name;
  std::string meaning;                   // one line for --help and the docs
  std::vector<std::string> assignments;  // "key=value", each a setting of slamSettings()
};

// The presets, in the order --help lists them. "offline": the cleanest person masks the learned
// detector gives (video matting and crop masks), at a few frames per second on two cores.
const std::vector<SlamPreset>& slamPresets();

// Sets the preset's assignments in `settings` (made by slamSettings()). Throws pf2::Error naming
// the preset and the presets there are when there is no such preset.
void applySlamPreset(const std::string& name, Settings* settings);

// Reads the keys of `config` into `options` (absent keys keep their values); fails on a key
// nobody declared or a value outside its range. Throws pf2::Error naming file, line and key.
void applyConfig(const ConfigFile& config, SlamOptions* options);

// Checks every setting against its declared range (values set in code); throws pf2::Error naming
// the setting, its value and the allowed range. SlamSystem's constructor calls it.
void validateOptions(const SlamOptions& options);

}  // namespace pf2
