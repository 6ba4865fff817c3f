#include "pf2/slam/slam_options.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "pf2/core/error.h"
#include "pf2/filters/filter_settings.h"

namespace pf2 {

DualBBoxFilter::Options SlamOptions::defaultFilterOptions() {
  DualBBoxFilter::Options options;
  // Backend masks on: with the learned detector 6 of 7 pf2_synth sequences track better with them
  // (xyz 3.1 mm instead of 11.4, loop 18.8 instead of 27.3) and the human tracks need them (8
  // identity switches without, gt masks); the real Bonn crowd frames track better with boxes only
  // (filter.use_mask false: 2.4 cm instead of 4.8; docs/BENCHMARKS.md, docs/DESIGN_NOTES.md).
  options.use_mask = true;
  // The box's depth rule only near the mask: Bonn crowd 4.8 cm (0 px: 9.6, 40 px: 7.7), pf2_synth
  // halfsphere with the learned detector 1.7 cm (0 px: 2.4, 40 px: 9.2); docs/BENCHMARKS.md.
  options.mask_box_reach = 20;
  options.temporal = true;
  options.geometric = true;
  // Depth the keyframes' prediction confirms as static is kept where only the box, ring or
  // temporal rule took it (pf2_synth halfsphere: 74 -> 90 % of the static depth kept, 98.5 ->
  // 98.2 % of the people removed; Bonn crowd 2.96 -> 1.9 cm; docs/BENCHMARKS.md).
  options.geometric_addition.keep_static = true;
  // ... and under a person's mask where it lies behind them (the mask's blurred edge over the
  // wall): pf2_synth hard cases 95.0-96.5 % of the static depth kept instead of 93.6-95.3, people
  // removed within 0.2 points; the tracker leaves those pixels out (SlamSystem), so its poses are
  // unchanged (docs/BENCHMARKS.md).
  options.keep_static_behind_masks = true;
  // Depth the box, ring or temporal rule took beside a mask but apart from the person's depth
  // there is given back (PersonDepthGate): pf2_synth hard cases 92.2 -> 94.2 % of the static depth
  // kept on average, 96.2 -> 96.0 % of the people removed; Bonn crowd windows 1.92 -> 1.57 cm mean,
  // within the +-0.15 cm any small filter change moves them (docs/BENCHMARKS.md).
  options.depth_gate.radius = 45;
  // A selfie component without a MoveNet pose that the segmenter is this sure of is a person even
  // without evidence: someone present since the first keyframe (so static to the prediction), cut
  // by the border or seated, is otherwise fused into the map. pf2_synth hard cases 96.0 -> 97.9 %
  // of the people removed (rpy 90.3 -> 95.1), seed 1 ATE 2.4 -> 0.8 mm (static). The selfie
  // model's few false components this sure on TUM fr1/rpy (no people) lie flat on the scene, and
  // the candidate's front test (GeometricAddition::Options::candidate_min_front) drops them;
  // docs/BENCHMARKS.md.
  options.geometric_addition.candidate_min_score = 0.95;
  return options;
}

DetectorOptions SlamOptions::defaultDetectionOptions() {
  DetectorOptions options;
  options.gt.provide_mask = true;
  return options;
}

Mapper::Options SlamOptions::defaultMapperOptions() {
  Mapper::Options options;
  options.max_stored_keyframes = 300;
  options.keep_radius = 10.0;
  return options;
}

namespace {

constexpr double kPi = 3.14159265358979;

// What the TSDF of a room with 100 m^2 of surface takes: the blocks along the truncation band
// (at least one 8-voxel block thick), 20-byte voxels, half as much again for the hash table and
// the blocks the band only grazes.
double mapBytesPerRoom(const TsdfVolume::Options& tsdf) {
  const double band = std::max(2.0 * tsdf.truncation, 8.0 * tsdf.voxel_size);
  const double voxels_per_m2 = band / (tsdf.voxel_size * tsdf.voxel_size * tsdf.voxel_size);
  return 100.0 * voxels_per_m2 * sizeof(TsdfVolume::Voxel) * 1.5;
}

// Three quarters of the machine's physical memory.
double usableMemoryBytes() {
  const double pages = static_cast<double>(::sysconf(_SC_PHYS_PAGES));
  const double page = static_cast<double>(::sysconf(_SC_PAGESIZE));
  return pages > 0 && page > 0 ? 0.75 * pages * page : 8e9;
}

void detectorSettings(SlamOptions& o, Settings& s) {
  std::vector<std::string> names{"auto", "none"};
  for (const std::string& name : humanDetectorNames()) names.push_back(name);
  s.choice("detector.name", &o.detector, names,
           "person detector, as `--detector`: auto = learned when its models are installed, else hog; "
           "gt = the ground-truth oracle of pf2_synth folders");
  s.boolean("detector.gt_masks", &o.detection.gt.provide_mask,
            "gt hands its masks to the filter like a segmenting detector; false = the paper's boxes only");
  declareBoxDegradationSettings("detector.gt_", &o.detection.gt.degradation, &s);
  s.integer("detector.pose_every", &o.learned_pose_every, 1, 30, "frames",
            "frames per MoveNet run of the learned detector");
  s.choice("detector.segmenter", &o.learned_segmenter, {"selfie", "rvm"},
           "the learned detector's person mask: selfie (real time) or rvm (video matting: outlines without "
           "chairs, about 8 x the time)");
  s.boolean("detector.crop_masks", &o.learned_crop_masks,
            "the learned detector completes the masks of people the selfie mask covers badly (cut by the "
            "border, a keypoint off the mask) and of candidates cut by the border with BlazePose's segmentation "
            "of a crop around each; about 0.7 of the selfie network's time per such person and frame: not real time");
  s.boolean("detector.candidate_poses", &o.learned_candidate_poses,
            "the learned detector runs MoveNet again on a crop around each large mask component no pose "
            "touches (a person close to the lens or cut by the border), on the frames MoveNet runs; a pose "
            "found there makes it a person");
  s.integer("detector.crop_size", &o.learned_crop_size, 192, 256, "pixels",
            "side of the crop network's input (detector.crop_masks): 192, 224 or 256; 192 takes 0.6 of "
            "256's time");
  s.require([&o] { return o.learned_crop_size % 32 == 0; }, "detector.crop_size is a multiple of 32",
            [&o] { return "detector.crop_size: expected 192, 224 or 256, got " + std::to_string(o.learned_crop_size); });
}

// The filter's own keys, then pf2_slam's geometric addition: the keyframes' prediction.
void filterSettings(SlamOptions& o, Settings& s) {
  declareFilterSettings(&o.filter, &s);
  s.number("filter.geometric_margin", &o.geometric_margin, 0.01, 2.0, "metres", "in front of the prediction by more: dynamic");
  s.integer("filter.geometric_opening", &o.geometric_opening, 0, 50, "pixels", "opening radius of the dynamic mask");
  s.integer("filter.geometric_keyframes", &o.prediction.keyframes, 1, 30, "keyframes", "keyframes the prediction is made from");
  s.number("filter.static_margin", &o.static_margin, 0.0, 1.0, "metres",
           "plus 1 % of the depth: this close to the prediction is known static (filter.keep_static)");
  s.number("filter.floor_margin", &o.floor_margin, 0.0, 0.5, "metres",
           "plus 1 % of the depth: this close to the floor plane is known static (filter.keep_static; 0 = off)");
  s.number("filter.behind_body_margin", &o.behind_body_margin, 0.0, 5.0, "metres",
           "depth under a posed person's mask more than this behind their body (their keypoints' depth band and "
           "their nearest keypoint's depth, humans.joint_band) goes to the map and masks/, not to the tracker: "
           "the mask's spill onto what stands behind them; 0 = off");
  s.integer("filter.backfill_frames", &o.backfill.frames, 0, 300, "frames",
            "the map and masks/ get each frame this many frames late, with the people found with a pose in "
            "those frames and in as many frames before it removed from it where their depth agrees (someone "
            "found late was there before, someone missed for a while has not left); the tracker does not wait; "
            "0 = off");
  s.number("filter.backfill_tolerance", &o.backfill.tolerance, 0.005, 0.5, "metres",
           "plus 1 % of the depth: a later person's point this close to a frame's depth removes it "
           "(filter.backfill_frames)");
  s.number("filter.backfill_floor_clearance", &o.backfill.floor_clearance, 0.0, 1.0, "metres",
           "a person's points lower than this above the floor are not carried (filter.backfill_frames)");
  s.number("filter.give_back_floor_clearance", &o.backfill.give_back_floor_clearance, 0.0, 1.0, "metres",
           "removed depth lower than this above the floor is never given back: people's feet stand on it "
           "(filter.give_back_views)");
  s.integer("filter.give_back_views", &o.backfill.give_back_views, 0, 10, "frames",
            "of every sixth frame in the filter.backfill_frames before and after a frame: this many must have "
            "seen a removed pixel's surface, kept (and twice as many as removed it), for the map and masks/ to "
            "get it back; 0 = off");
  s.number("filter.give_back_tolerance", &o.backfill.give_back_tolerance, 0.005, 0.5, "metres",
           "plus 1 % of the depth: another frame's kept depth this close to a removed point sees its surface "
           "(filter.give_back_views)");
  s.integer("filter.seen_through_views", &o.backfill.seen_through_views, 0, 10, "frames",
            "of every sixth frame in the filter.backfill_frames before and after a frame: this many must have "
            "seen through a kept pixel's point (kept what they measured behind it), and no more than one kept "
            "its surface, for the map and masks/ to lose it as someone who moved; 0 = off");
  s.number("filter.seen_through_margin", &o.backfill.seen_through_margin, 0.02, 1.0, "metres",
           "plus 3 % of the depth: another frame's depth this far behind a point all around its pixel sees "
           "through it (filter.seen_through_views)");
}

void odometrySettings(RgbdOdometry::Options& d, Settings& s) {
  s.integer("tracker.pyramid_levels", &d.pyramid_levels, 1, 6, "levels", "odometry pyramid levels, each half the size");
  s.integer("tracker.finest_level", &d.finest_level, 0, 5, "level", "finest level iterated (1 = stop at half size)");
  s.require([&d] { return d.finest_level < d.pyramid_levels; },
            "tracker.finest_level must lie in the range [0, tracker.pyramid_levels - 1]");
  s.number("tracker.photometric_weight", &d.photometric_weight, 0.0, 100.0, "weight",
           "weight of the photometric term (0 = ICP only)");
  s.boolean("tracker.features_every_frame", &d.features_every_frame, "ORB + RANSAC on every frame, not only on failure");
  s.number("tracker.prior_sigma_translation", &d.prior_sigma_translation, 0.0, 10.0, "metres",
           "motion prior per frame (0 = none)");
  s.number("tracker.prior_sigma_rotation", &d.prior_sigma_rotation, 0.0, kPi, "radians", "motion prior per frame (0 = none)");
  s.number("tracker.depth_sigma", &d.depth_sigma, 1e-4, 1.0, "metres", "depth noise at 1 m (grows with z squared)");
  s.number("tracker.depth_sigma_floor", &d.depth_sigma_floor_depth, 0.0, 10.0, "metres",
           "nearer points are weighted as if at this depth (0 = the z squared noise all the way)");
  s.number("tracker.intensity_sigma", &d.intensity_sigma, 1e-3, 1.0, "intensity", "largest photometric noise");
  s.number("tracker.min_intensity_sigma", &d.min_intensity_sigma, 0.0, 1.0, "intensity",
           "smallest measured photometric noise (0 = always tracker.intensity_sigma)");
  s.require([&d] { return d.min_intensity_sigma <= d.intensity_sigma; },
            "tracker.min_intensity_sigma must lie in the range [0, tracker.intensity_sigma]");
  s.integer("tracker.max_points_per_level", &d.max_points_per_level, 100, 1000000, "samples", "dense samples per level");
  s.integer("tracker.iterations_coarse", &d.iterations_coarse, 1, 100, "iterations", "Gauss-Newton, coarsest level");
  s.integer("tracker.iterations_fine", &d.iterations_fine, 1, 100, "iterations", "Gauss-Newton, finest level");
  s.number("tracker.huber_k", &d.huber_k, 0.1, 100.0, "sigmas",
           "Huber threshold on normalised point-to-plane residuals");
  s.number("tracker.photometric_huber_k", &d.photometric_huber_k, 0.1, 100.0, "sigmas",
           "Huber threshold on normalised photometric residuals");
  s.integer("tracker.person_mask_dilation", &d.person_mask_dilation, 0, 100, "pixels",
            "added around person masks before they are cut out of the odometry");
}

void trackerSettings(SlamOptions& o, Settings& s) {
  Tracker::Options& t = o.tracker;
  odometrySettings(t.odometry, s);
  s.integer("tracker.max_bridged_frames", &t.max_bridged_frames, 0, 300, "frames",
            "frames in a row given the motion prior's pose before the camera counts as lost");
  s.number("trajectory.position_noise", &o.trajectory.position_noise, 0.0, 1.0, "metres",
           "scatter of one frame's measured camera position, for the smoothing of trajectory.txt (0 = none)");
  s.number("trajectory.acceleration_noise", &o.trajectory.acceleration_noise, 0.01, 1000.0, "m/s^2",
           "typical acceleration of the camera per axis (RMS), for the smoothing of trajectory.txt, where the run "
           "does not measure its own (trajectory.measure_acceleration false, or a run under three baselines)");
  s.boolean("trajectory.measure_acceleration", &o.trajectory.measure_acceleration,
            "the smoothing's acceleration noise measured from the run's own positions (stats.json "
            "trajectory_acceleration_noise)");
  s.number("trajectory.acceleration_baseline", &o.trajectory.acceleration_baseline, 0.05, 10.0, "seconds",
           "time step of the second differences the run's acceleration is measured with");
  s.number("trajectory.acceleration_scale", &o.trajectory.acceleration_scale, 0.1, 100.0, "factor",
           "measured acceleration noise = this x the run's RMS acceleration along its busiest axis");
  s.number("trajectory.acceleration_floor", &o.trajectory.acceleration_floor, 0.001, 1000.0, "m/s^2",
           "the least measured acceleration noise");
  s.number("trajectory.max_gap", &o.trajectory.max_gap, 0.0, 60.0, "seconds", "frames further apart: smoothed apart");
  s.number("trajectory.fill_gaps", &o.gaps.max_gap, 0.0, 60.0, "seconds",
           "frames without a measured pose (bridged or lost) between two measured frames at most this far apart get "
           "poses interpolated between them at the end of the run (0 = never)");
  s.number("trajectory.fill_velocity_window", &o.gaps.velocity_window, 0.01, 5.0, "seconds",
           "a filled gap's end velocities are measured over this much time before and after it");
  s.number("tracker.min_agreement", &t.min_tracking_agreement, 0.0, 1.0, "fraction",
           "a frame's alignment to its keyframe needs this share of inliers among its associated points "
           "(else the previous frame is tried; 0 = no check)");
  s.integer("tracker.local_edges", &t.backend.local_edges, 0, 9, "keyframes",
            "each new keyframe is also aligned onto up to this many near keyframes among the previous nine (0 = chain and loops)");
  s.number("tracker.local_radius", &t.backend.local_radius, 0.0, 10.0, "metres", "of the local window");
  s.number("tracker.local_max_angle", &t.backend.local_max_angle, 0.0, kPi, "radians", "of the local window");
  s.number("tracker.keyframe_translation", &t.keyframes.max_translation, 0.01, 5.0, "metres", "new keyframe after");
  s.number("tracker.keyframe_rotation", &t.keyframes.max_rotation, 0.01, kPi, "radians", "new keyframe after");
  s.number("tracker.min_keyframe_depth_fraction", &t.min_keyframe_depth_fraction, 0.0, 1.0, "fraction",
           "a keyframe needs at least this share of pixels with usable (static) depth");
  s.boolean("tracker.asynchronous_backend", &t.asynchronous_backend, "pose graph in its own thread");
}

void humanSettings(SlamOptions& o, Settings& s) {
  HumanTracker::Options& h = o.humans;
  s.boolean("humans.track", &o.track_humans, "write humans.txt (needs a detector)");
  s.boolean("humans.depth_in_interval", &o.human_depth_in_interval,
            "d_m over the person's depths inside their interval; false = all of D_h^t (the paper)");
  s.number("humans.joint_band", &o.human_joint_band, 0.0, 5.0, "metres",
           "a masked person's d_m and body fit use only their depths this near the median depth under their confident keypoints (0 = off)");
  s.number("humans.joint_min_share", &o.human_joint_min_share, 0.0, 1.0, "fraction",
           "humans.joint_band applies when at least this share of the person's depths lie in it");
  s.number("humans.group_gap", &o.human_group_gap, 0.0, 5.0, "metres",
           "a person without a keypoint band whose depths fall into groups this far apart is placed and fitted on the "
           "largest group (0 = off)");
  s.number("humans.group_min_share", &o.human_group_min_share, 0.0, 0.5, "fraction",
           "humans.group_gap applies when the other groups hold at least this share of the person's depths");
  s.boolean("humans.box_from_depths", &o.human_box_from_depths,
            "a centre's box is that of the depths d_m rests on; false = the detector's box (eq. 2 as written)");
  s.number("humans.max_outside_pose", &o.human_max_outside_pose, 0.01, 1.0, "share",
           "a person more of whose depths lie outside the region their keypoints give, and behind it, is placed and "
           "fitted on those inside (1 = never)");
  s.number("humans.box_trim", &o.human_box_trim, 0.0, 0.45, "fraction",
           "humans.box_from_depths: each side of the box moved in past this share of the depths");
  s.number("humans.min_area", &o.human_min_area, 0.0, 1.0, "fraction", "no centre for a person covering less of the image");
  s.number("humans.same_body", &o.human_same_body, 0.0, 2.0, "metres",
           "of two centres of one frame this near each other, the one on fewer depths is dropped (one body; 0 = off)");
  s.integer("humans.min_frames", &o.human_min_frames, 1, 100000, "frames",
            "a track seen in fewer frames is left out of humans.txt and humans.json (a false detection)");
  s.custom("humans.association",
           [&h](const std::string& text) { h.association = humanAssociationFromName(text); },
           [&h] { return toString(h.association); }, "predicted, paper",
           "predicted: constant velocity, gated Hungarian; paper: closest centre of the previous frame");
  s.number("humans.gate", &h.gate, 0.05, 10.0, "metres", "largest distance between a track's prediction and a centre");
  s.number("humans.gate_growth", &h.gate_growth, 0.0, 10.0, "m/s", "gate growth while a track is unseen");
  s.number("humans.still_speed", &h.still_speed, 0.0, 10.0, "m/s",
           "a person whose track moved slower than this when last seen is looked for within a gate growing by "
           "humans.still_gate_growth instead of humans.gate_growth while unseen (0 = off)");
  s.number("humans.still_gate_growth", &h.still_gate_growth, 0.0, 10.0, "m/s",
           "how fast the gate of a person last seen standing (humans.still_speed) grows while they are unseen");
  s.number("humans.max_acceleration", &h.max_acceleration, 0.0, 20.0, "m/s^2",
           "a new track is re-identified as a lost one only where its person could have walked while unseen, from the "
           "lost track's speed, speeding up at most this much (0 = off)");
  s.integer("humans.max_missed", &h.max_missed, 0, 100000, "frames", "a track lives this long unseen");
  s.number("humans.velocity_window", &h.velocity_window, 0.01, 10.0, "seconds", "a track's velocity is measured over");
  s.number("humans.max_speed", &h.max_speed, 0.1, 20.0, "m/s", "velocity clamp");
  s.number("humans.reid_window", &h.reid_window, 0.0, 3600.0, "seconds",
           "a person unseen this long can be re-identified by appearance and position (0 = never)");
  s.number("humans.appearance_weight", &h.appearance_weight, 0.0, 10.0, "",
           "association cost per unit of appearance dissimilarity (0 = position only)");
  s.number("humans.appearance_crowd", &h.appearance_crowd, 0.0, 10.0, "metres",
           "a centre this near another live track's prediction does not update its track's appearance (0 = always)");
  s.number("humans.reid_similarity", &h.reid_similarity, 0.0, 1.0, "",
           "colour-histogram similarity (Bhattacharyya coefficient) needed to re-identify a person");
  s.number("humans.reid_speed_cost", &h.reid_speed_cost, 0.0, 10.0, "per m/s",
           "similarity taken off a lost track's claim per m/s its person must have walked while unseen (0 = off)");
  s.number("humans.reid_near_similarity", &h.reid_near_similarity, 0.0, 1.0, "",
           "similarity needed to re-identify a person back within humans.reid_near_time where they were lost");
  s.number("humans.reid_near_time", &h.reid_near_time, 0.0, 60.0, "seconds",
           "a person back within this time and within the gate of where they were lost needs only "
           "humans.reid_near_similarity (0 = off)");
  s.integer("humans.reid_after", &h.reid_after, 1, 1000, "frames",
            "a new track is compared with lost ones once it has this many centres, and ends when missed before "
            "(1 = at first sight)");
  s.integer("humans.reid_checks", &h.reid_checks, 1, 8, "comparisons",
            "a new track not re-identified is compared again at 2 x, 4 x ... humans.reid_after centres (1 = once)");
  s.number("humans.occluder_margin", &h.occluder_margin, 0.0, 5.0, "metres",
           "a new track first seen this much nearer the camera than a lost track's last centres, on the line of "
           "sight to them, is not re-identified as it (the person who hid them; 0 = off)");
  s.number("humans.occluder_window", &h.occluder_window, 0.0, 60.0, "seconds",
           "humans.occluder_margin applies to tracks lost at most this long before the new one was first seen");
}

void bodySettings(SlamOptions& o, Settings& s) {
  BodyTrackFitter::Options& b = o.bodies;
  s.boolean("bodies.fit", &o.fit_bodies, "fit each tracked person's body (needs keypoints); as --no-bodies when false");
  s.integer("bodies.fit_every", &b.fit_every, 1, 300, "frames", "frames between two fits of one person");
  s.number("bodies.min_keypoints_on_person", &o.body_min_keypoints_on_person, 0.0, 1.0, "",
           "share of a person's confident keypoints that must lie on their own depth for a fit (0 = always fit)");
  s.integer("bodies.queue", &b.queue_capacity, 1, 1000, "fits", "fits waiting for the body thread; more are skipped");
  s.integer("bodies.shape_fits", &b.shape_fits, 1, 1000, "fits", "fits of a person with a free shape, then it is held");
  s.number("bodies.warm_start_gap", &b.warm_start_gap, 0.0, 10.0, "seconds", "an older fit is not a warm start");
  s.number("bodies.max_start_depth_gap", &b.max_start_depth_gap, 0.0, 10.0, "metres",
           "a warm start whose pelvis lies farther in depth from the person's median depth is not used (0 = no check)");
  s.number("bodies.min_pose_size", &b.min_pose_size, 0.0, 2.0, "metres",
           "a pose whose longest torso side or limb segment is shorter at the person's depth is not fitted (0 = no check)");
  s.number("bodies.min_torso_side", &b.min_torso_side, 0.0, 2.0, "metres",
           "a pose with a torso side (shoulder to hip) in full view shorter than this at the person's depth is not "
           "fitted: a whole body squeezed into the part of a near person in view (0 = no check)");
  s.number("bodies.weight_temporal", &b.weight_temporal, 0.0, 100.0, "", "pull towards the previous fit's pose");
  s.boolean("bodies.asynchronous", &b.asynchronous, "fits in their own thread; false: in the front end (repeatable)");
  s.boolean("bodies.keypoint_offsets", &b.fitter.keypoint_offsets,
            "COCO keypoints lie beside their joints as measured for MoveNet (hips, shoulders, ankles 2-3 cm up the "
            "bone); false: at the joints");
  s.number("bodies.side_view_separation", &b.fitter.side_view_separation, 0.0, 1.0, "metres",
           "a left/right keypoint pair closer than this in the image is seen from the side: the hidden one's depth "
           "term only keeps it behind the surface it falls on (0 = off)");
  s.number("bodies.edge_band", &b.fitter.edge_band, 0.0, 100.0, "pixels",
           "a keypoint this close to an image edge, or beyond it, only says the joint lies at or beyond that edge");
  s.number("bodies.weight_upright", &b.fitter.weight_upright, 0.0, 1000.0, "",
           "pull of each fit's up axis towards the world's up (about this x the lean in radians; 0 = none)");
  s.boolean("bodies.surface_alignment", &b.fitter.surface_alignment,
            "move each fit along its pelvis ray onto the person's measured torso surface, then fit again from there");
  s.number("bodies.surface_quantile", &b.fitter.surface.quantile, 0.01, 0.99, "",
           "quantile of (measured - body) torso depth the surface alignment moves the body to (0.5 = median; above "
           "it, because arms and people in front of a torso are what lies wrongly in its pixels)");
  s.number("bodies.weight_surface_depth", &b.fitter.weight_surface_depth, 0.0, 100000.0, "",
           "after the surface alignment, hold of the body's depth (1000: 1 cm weighs like 10 px)");
  s.boolean("bodies.refine_keypoints", &o.refine_keypoints,
            "before each fit, MoveNet runs again on a crop around the person (learned and movenet detectors)");
  s.integer("bodies.refine_input", &o.keypoint_refiner.input_size, 64, 512, "pixels",
            "side of the crop at MoveNet's input, a multiple of 32");
  s.require([&o] { return o.keypoint_refiner.input_size % 32 == 0; }, "bodies.refine_input is a multiple of 32",
            [&o] { return "bodies.refine_input: expected a multiple of 32, got " +
                          std::to_string(o.keypoint_refiner.input_size); });
  s.number("bodies.refine_margin", &o.keypoint_refiner.margin, 0.0, 2.0, "",
           "the crop's side is (1 + this) times the person's box's longer side");
  s.number("bodies.max_gap", &o.body_tracks.max_gap, 0.0, 60.0, "seconds", "fits further apart are not interpolated");
  s.number("bodies.velocity_span", &o.body_tracks.velocity_span, 0.0, 10.0, "seconds",
           "between fits the pelvis follows a cubic curve with the velocity over this span beyond each (0 = a line)");
  s.number("bodies.max_extrapolation", &o.body_tracks.max_extrapolation, 0.0, 10.0, "seconds",
           "frames this close before a track's first fit or after its last move on with the track's velocity (0 = off)");
  s.number("bodies.centre_sigma", &o.body_tracks.centre_sigma, 0.0, 1.0, "metres",
           "spread of the pelvis the eq. 2 centre gives; frames moved on by bodies.max_extrapolation are drawn "
           "towards it as the extrapolation grows less certain (0 = the extrapolation alone)");
  s.number("bodies.extrapolation_acceleration", &o.body_tracks.extrapolation_acceleration, 0.0, 20.0, "m/s^2",
           "change of pace a person may make after their last fit: the extrapolation's uncertainty is 1/2 a t^2");
  s.number("bodies.smoothing", &o.body_tracks.smoothing_sigma, 0.0, 5.0, "seconds",
           "sigma of the Gaussian smoothing of each person's pelvis over time (0 = none)");
  s.number("bodies.pose_smoothing", &o.body_tracks.pose_smoothing_sigma, 0.0, 5.0, "seconds",
           "sigma of the Gaussian smoothing of each person's joint rotations over time (0 = none)");
  s.number("bodies.max_offset_deviation", &o.body_tracks.max_offset_deviation, 0.01, 10.0, "metres",
           "a fit whose pelvis is further from where the person's other fits lie (relative to the eq. 2 centre) is dropped");
  s.number("bodies.max_path_deviation", &o.body_tracks.max_path_deviation, 0.0, 10.0, "metres",
           "a fit whose pelvis is further from the line between the fits before and after it is dropped; one closer "
           "to the line between the fits kept around it, when those are more than bodies.max_gap apart, is kept "
           "whatever its offset (0 = off)");
  s.boolean("bodies.visible_centre", &o.body_tracks.visible_centre,
            "a person far from any fit is placed where the nearest fit's body gives their eq. 2 centre in the image "
            "(the part inside it only), and a fit of a person cut by the border is judged by that centre; false: at "
            "the centre plus the fit's offset, every fit judged by its offset");
  s.number("bodies.cut_bias_window", &o.body_tracks.cut_bias_window, 0.0, 60.0, "seconds",
           "with bodies.visible_centre, a fit of a person cut by the border is judged against the person's fits "
           "within this time of it (at least three; 0 = all of the person's fits)");
  s.boolean("bodies.hold_height", &o.body_tracks.hold_height,
            "a person far from any fit keeps the nearest fit's pelvis height, only their horizontal position comes "
            "from the eq. 2 centre; false: the centre's height too");
  s.integer("bodies.scene_every", &o.scene.bodies_every, 0, 100000, "frames",
            "scene.ply/.obj also show every n-th body along each track (0 = the last fitted body only)");
}

void mapSettings(SlamOptions& o, Settings& s) {
  Mapper::Options& m = o.mapper;
  s.boolean("map.build", &o.build_map, "fuse the map (TSDF and OctoMap)");
  s.boolean("map.synchronous", &o.synchronous_map,
            "fuse in the front end's thread: the same map on every run (with tracker.asynchronous_backend false), slower");
  s.boolean("map.follow_corrections", &o.follow_corrections,
            "re-fuse the keyframes the pose graph moved after every correction; false: once, at the end (the "
            "same final map, less work)");
  s.integer("map.fuse_every", &o.fuse_every, 0, 1000, "frames",
            "also fuse every n-th tracked frame between keyframes (0 = keyframes only)");
  s.number("map.voxel_size", &m.tsdf.voxel_size, 0.002, 0.2, "metres", "TSDF voxel edge");
  s.number("map.truncation", &m.tsdf.truncation, 0.004, 1.0, "metres", "TSDF truncation distance");
  s.require([&m] { return m.tsdf.truncation >= m.tsdf.voxel_size; }, "map.truncation must lie in the range [map.voxel_size, 1]");
  s.require([&m] { return mapBytesPerRoom(m.tsdf) <= usableMemoryBytes(); },
            "the TSDF of a 100 m^2 room (map.voxel_size, map.truncation) must fit in three quarters of the "
            "machine's memory",
            [&m] {
              char text[320];
              std::snprintf(text, sizeof(text),
                            "map.voxel_size = %g m with map.truncation = %g m: the map of a 100 m^2 room would need "
                            "about %.1f GB, more than the %.1f GB this machine can give it; use a larger voxel or a "
                            "smaller truncation",
                            m.tsdf.voxel_size, m.tsdf.truncation, mapBytesPerRoom(m.tsdf) / 1e9,
                            usableMemoryBytes() / 1e9);
              return std::string(text);
            });
  s.number("map.max_depth", &m.tsdf.max_depth, 0.3, 20.0, "metres", "depth beyond is not fused");
  s.boolean("map.octomap", &m.build_occupancy, "build the OctoMap");
  s.number("map.octomap_resolution", &m.occupancy.resolution, 0.01, 1.0, "metres", "OctoMap leaf size");
  s.integer("map.octomap_stride", &m.occupancy.pixel_stride, 1, 64, "pixels",
            "every n-th pixel (both axes) becomes an OctoMap ray");
  s.integer("map.max_stored_keyframes", &m.max_stored_keyframes, 0, 100000, "keyframes",
            "keyframes kept re-integrable (0 = unbounded)");
  s.number("map.keep_radius", &m.keep_radius, 0.0, 1000.0, "metres", "TSDF kept around the camera (0 = unbounded)");
  s.boolean("map.pcd", &o.map_files.points_pcd, "also write map.pcd");
  s.boolean("map.obj", &o.map_files.mesh_obj, "also write map.obj");
}

void runSettings(SlamOptions& o, Settings& s) {
  s.integer("run.max_frames", &o.max_frames, 0, 100000000, "frames", "frames processed from the start (0 = all)");
  s.integer("run.prefetch_frames", &o.prefetch_frames, 1, 64, "frames", "frames decoded ahead in a loader thread");
  s.boolean("run.progress", &o.progress, "progress line with fps on standard error");
  s.integer("run.opencv_threads", &o.opencv_threads, 0, 64, "threads",
            "threads of OpenCV's own parallel loops (DNN inference, resizing); 0 = one per core");
  s.boolean("run.write_masks", &o.write_masks,
            "write masks/<timestamp>.png per frame, 255 = depth the filter removed (as --masks)");
}

}  // namespace

Settings slamSettings(SlamOptions* options) {
  Settings settings;
  detectorSettings(*options, settings);
  filterSettings(*options, settings);
  trackerSettings(*options, settings);
  humanSettings(*options, settings);
  bodySettings(*options, settings);
  mapSettings(*options, settings);
  runSettings(*options, settings);
  return settings;
}

const std::vector<SlamPreset>& slamPresets() {
  // Measured in docs/BENCHMARKS.md ("Crop masks"): with the matte and the crop masks every
  // tracking and removal target of the shared sequences is met, at 7-8 fps on two cores instead
  // of 25-28. Their masks follow people's outlines, so what the box, ring and temporal rules take
  // beside them is mostly background: the map keeps it, the tracker still leaves it out (its
  // input, and so the poses, unchanged).
  static const std::vector<SlamPreset> kPresets = {
      {"offline", "video matting and crop masks, the map keeping what the rules beside them take: the cleanest maps, about 7-8 fps on 2 cores",
       {"detector.segmenter=rvm", "detector.crop_masks=true", "filter.outside_masks_tracker_only=true"}}};
  return kPresets;
}

void applySlamPreset(const std::string& name, Settings* settings) {
  std::string names;
  for (const SlamPreset& preset : slamPresets()) {
    if (preset.name == name) {
      for (const std::string& assignment : preset.assignments) settings->setAssignment(assignment);
      return;
    }
    names += (names.empty() ? "" : ", ") + preset.name;
  }
  throw Error("no preset '" + name + "' (presets: " + names + ")");
}

void applyConfig(const ConfigFile& config, SlamOptions* options) { slamSettings(options).apply(config); }

void validateOptions(const SlamOptions& options) {
  SlamOptions checked = options;
  slamSettings(&checked).validate();
}

}  // namespace pf2
