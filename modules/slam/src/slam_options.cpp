#include "pf2/slam/slam_options.h"

#include <limits>
#include <sstream>

#include "pf2/core/error.h"

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

void applyConfig(const ConfigFile& config, SlamOptions* options) {
  SlamOptions& o = *options;
  o.detector = config.text("detector.name", o.detector);
  o.detection.gt.provide_mask = config.boolean("detector.gt_masks", o.detection.gt.provide_mask);
  o.detection.gt.degradation.shrink = config.number("detector.gt_shrink", o.detection.gt.degradation.shrink);
  o.detection.gt.degradation.drop_probability =
      config.number("detector.gt_drop", o.detection.gt.degradation.drop_probability);

  DualBBoxFilter::Options& f = o.filter;
  f.min_confidence = config.number("filter.min_confidence", f.min_confidence);
  f.box_scale = config.number("filter.box_scale", f.box_scale);
  f.background_margin = config.number("filter.background_margin", f.background_margin);
  f.human_margin = config.number("filter.human_margin", f.human_margin);
  f.human_histogram.surround_weight = config.number("filter.surround_weight", f.human_histogram.surround_weight);
  f.surround_scale = config.number("filter.surround_scale", f.surround_scale);
  f.separate_occlusions = config.boolean("filter.separate_occlusions", f.separate_occlusions);
  f.use_mask = config.boolean("filter.use_mask", f.use_mask);
  f.mask_dilation = config.integer("filter.mask_dilation", f.mask_dilation);
  f.mask_box_reach = config.integer("filter.mask_reach", f.mask_box_reach);
  f.temporal = config.boolean("filter.temporal", f.temporal);
  f.geometric = config.boolean("filter.geometric", f.geometric);
  o.geometric_margin = config.number("filter.geometric_margin", o.geometric_margin);
  f.candidate_min_dynamic = config.number("filter.candidate_min_dynamic", f.candidate_min_dynamic);
  f.candidate_memory = config.integer("filter.candidate_memory", f.candidate_memory);
  o.geometric_opening = config.integer("filter.geometric_opening", o.geometric_opening);
  o.prediction.keyframes = config.integer("filter.geometric_keyframes", o.prediction.keyframes);

  Tracker::Options& t = o.tracker;
  t.odometry.pyramid_levels = config.integer("tracker.pyramid_levels", t.odometry.pyramid_levels);
  t.odometry.finest_level = config.integer("tracker.finest_level", t.odometry.finest_level);
  t.odometry.photometric_weight = config.number("tracker.photometric_weight", t.odometry.photometric_weight);
  t.odometry.prior_sigma_translation =
      config.number("tracker.prior_sigma_translation", t.odometry.prior_sigma_translation);
  t.odometry.prior_sigma_rotation = config.number("tracker.prior_sigma_rotation", t.odometry.prior_sigma_rotation);
  t.odometry.depth_sigma = config.number("tracker.depth_sigma", t.odometry.depth_sigma);
  t.odometry.intensity_sigma = config.number("tracker.intensity_sigma", t.odometry.intensity_sigma);
  t.odometry.min_intensity_sigma = config.number("tracker.min_intensity_sigma", t.odometry.min_intensity_sigma);
  t.max_bridged_frames = config.integer("tracker.max_bridged_frames", t.max_bridged_frames);
  t.backend.local_edges = config.integer("tracker.local_edges", t.backend.local_edges);
  t.backend.local_radius = config.number("tracker.local_radius", t.backend.local_radius);
  t.backend.local_max_angle = config.number("tracker.local_max_angle", t.backend.local_max_angle);
  t.odometry.max_points_per_level = config.integer("tracker.max_points_per_level", t.odometry.max_points_per_level);
  t.odometry.iterations_coarse = config.integer("tracker.iterations_coarse", t.odometry.iterations_coarse);
  t.odometry.iterations_fine = config.integer("tracker.iterations_fine", t.odometry.iterations_fine);
  t.odometry.huber_k = config.number("tracker.huber_k", t.odometry.huber_k);
  t.odometry.person_mask_dilation = config.integer("tracker.person_mask_dilation", t.odometry.person_mask_dilation);
  t.odometry.features_every_frame =
      config.boolean("tracker.features_every_frame", t.odometry.features_every_frame);
  t.keyframes.max_translation = config.number("tracker.keyframe_translation", t.keyframes.max_translation);
  t.keyframes.max_rotation = config.number("tracker.keyframe_rotation", t.keyframes.max_rotation);
  t.asynchronous_backend = config.boolean("tracker.asynchronous_backend", t.asynchronous_backend);

  HumanTracker::Options& h = o.humans;
  o.track_humans = config.boolean("humans.track", o.track_humans);
  o.human_depth_in_interval = config.boolean("humans.depth_in_interval", o.human_depth_in_interval);
  o.human_min_area = config.number("humans.min_area", o.human_min_area);
  try {
    h.association = humanAssociationFromName(config.text("humans.association", toString(h.association)));
  } catch (const Error& e) {
    throw Error(std::string("config key humans.association: ") + e.what());
  }
  h.gate = config.number("humans.gate", h.gate);
  h.gate_growth = config.number("humans.gate_growth", h.gate_growth);
  h.max_missed = config.integer("humans.max_missed", h.max_missed);
  h.velocity_window = config.number("humans.velocity_window", h.velocity_window);
  h.max_speed = config.number("humans.max_speed", h.max_speed);

  Mapper::Options& m = o.mapper;
  o.build_map = config.boolean("map.build", o.build_map);
  o.fuse_every = config.integer("map.fuse_every", o.fuse_every);
  m.tsdf.voxel_size = config.number("map.voxel_size", m.tsdf.voxel_size);
  m.tsdf.truncation = config.number("map.truncation", m.tsdf.truncation);
  m.tsdf.max_depth = config.number("map.max_depth", m.tsdf.max_depth);
  m.build_occupancy = config.boolean("map.octomap", m.build_occupancy);
  m.occupancy.resolution = config.number("map.octomap_resolution", m.occupancy.resolution);
  m.max_stored_keyframes = config.integer("map.max_stored_keyframes", m.max_stored_keyframes);
  m.keep_radius = config.number("map.keep_radius", m.keep_radius);
  o.map_files.points_pcd = config.boolean("map.pcd", o.map_files.points_pcd);
  o.map_files.mesh_obj = config.boolean("map.obj", o.map_files.mesh_obj);

  o.max_frames = config.integer("run.max_frames", o.max_frames);
  o.prefetch_frames = config.integer("run.prefetch_frames", o.prefetch_frames);
  o.progress = config.boolean("run.progress", o.progress);
  config.checkAllUsed();
}

namespace {

// Throws pf2::Error naming the key, the value and the allowed range when value is outside [lo, hi].
void checkRange(const char* key, double value, double lo, double hi, const char* unit) {
  if (value >= lo && value <= hi) return;
  std::ostringstream message;
  message << "setting " << key << " = " << value << " is outside its range [" << lo << ", " << hi << "] "
          << unit;
  throw Error(message.str());
}

}  // namespace

void validateOptions(const SlamOptions& o) {
  const double inf = std::numeric_limits<double>::infinity();
  checkRange("filter.mask_reach", o.filter.mask_box_reach, 0, 200, "pixels");
  checkRange("filter.geometric_margin", o.geometric_margin, 0.01, 2.0, "metres");
  checkRange("filter.candidate_min_dynamic", o.filter.candidate_min_dynamic, 0.0, 1.0,
             "fraction of a candidate's pixels (0 = candidates ignored)");
  checkRange("filter.candidate_memory", o.filter.candidate_memory, 0, 254, "frames");
  checkRange("filter.geometric_opening", o.geometric_opening, 0, 50, "pixels");
  checkRange("filter.geometric_keyframes", o.prediction.keyframes, 1, 10, "keyframes");
  const RgbdOdometry::Options& d = o.tracker.odometry;
  checkRange("tracker.prior_sigma_translation", d.prior_sigma_translation, 0, inf, "metres (0 = no prior)");
  checkRange("tracker.prior_sigma_rotation", d.prior_sigma_rotation, 0, inf, "radians (0 = no prior)");
  checkRange("tracker.depth_sigma", d.depth_sigma, 1e-4, 1.0, "metres at 1 m");
  checkRange("tracker.intensity_sigma", d.intensity_sigma, 1e-3, 1.0, "intensity [0, 1]");
  checkRange("tracker.min_intensity_sigma", d.min_intensity_sigma, 0, d.intensity_sigma,
             "intensity (0 = not measured; at most tracker.intensity_sigma)");
  checkRange("tracker.max_bridged_frames", o.tracker.max_bridged_frames, 0, 300, "frames");
  checkRange("tracker.max_points_per_level", d.max_points_per_level, 100, 1000000, "samples");
  checkRange("tracker.iterations_coarse", d.iterations_coarse, 1, 100, "iterations");
  checkRange("tracker.iterations_fine", d.iterations_fine, 1, 100, "iterations");
  checkRange("tracker.huber_k", d.huber_k, 0.1, 100.0, "normalised residual");
  checkRange("tracker.person_mask_dilation", d.person_mask_dilation, 0, 100, "pixels");
  checkRange("tracker.local_edges", o.tracker.backend.local_edges, 0, 9, "keyframes");
  checkRange("tracker.local_radius", o.tracker.backend.local_radius, 0.0, 10.0, "metres");
  checkRange("tracker.local_max_angle", o.tracker.backend.local_max_angle, 0.0, 3.15, "radians");
}

}  // namespace pf2
