#include "pf2/filters/filter_settings.h"

namespace pf2 {
namespace {

void paperSettings(DualBBoxFilter::Options* f, Settings* s) {
  s->number("filter.min_confidence", &f->min_confidence, 0.0, 1.0, "score", "boxes with a higher score are used");
  s->number("filter.box_scale", &f->box_scale, 1.0, 3.0, "factor", "lambda: box enlargement for the ring");
  s->number("filter.background_margin", &f->background_margin, 0.0, 2.0, "metres", "margin around (b_min, b_max)");
  s->number("filter.human_margin", &f->human_margin, 0.0, 2.0, "metres", "margin around (h_min, h_max)");
  HistogramOptions& h = f->human_histogram;
  s->number("filter.bin_width", &h.bin_width, 0.005, 0.5, "metres", "bin of a person's depth histogram");
  s->number("filter.background_bin_width", &f->background_histogram.bin_width, 0.005, 0.5, "metres",
            "bin of the background's depth histogram");
  s->number("filter.human_window", &h.window, 0.1, 5.0, "metres", "width of a person's principal depth window");
  s->number("filter.grow_fraction", &h.grow_fraction, 0.0, 1.0, "fraction",
            "the window grows into bins holding at least this share of its mean bin");
  s->number("filter.near_preference", &h.near_preference, 0.0, 1.0, "fraction",
            "the nearest window holding this share of the best one's count wins (1 = plain maximum)");
  s->number("filter.surround_weight", &h.surround_weight, 0.0, 1.0, "weight",
            "share of the surround's depth density taken off a person's histogram (docs/filters.md)");
  s->number("filter.surround_scale", &f->surround_scale, 1.0, 5.0, "factor", "box enlargement giving the surround");
  s->boolean("filter.separate_occlusions", &f->separate_occlusions, "overlapping boxes that found one person look again");
}

void additionSettings(DualBBoxFilter::Options* f, Settings* s) {
  s->boolean("filter.use_mask", &f->use_mask, "use the detector's person masks");
  s->integer("filter.mask_dilation", &f->mask_dilation, 0, 50, "pixels", "dilation of a person mask");
  s->integer("filter.mask_reach", &f->mask_box_reach, 0, 200, "pixels",
             "with masks, the box and ring rules act only this near a person's mask (0 = everywhere, the paper)");
  s->integer("filter.joint_min_count", &f->joint_min_count, 0, 17, "keypoints",
             "with masks, a person's interval is taken again near the median depth under at least this many "
             "confident keypoints when it lies outside it (0 = off)");
  s->number("filter.joint_min_score", &f->joint_min_score, 0.0, 1.0, "score", "confident keypoint: at least this score");
  s->integer("filter.depth_gate_radius", &f->depth_gate.radius, 0, 100, "pixels",
             "with masks, depth the box, ring or temporal rule removed outside the masks is given back when it lies "
             "apart from the masked person depth within this window (0 = off, the paper)");
  s->number("filter.depth_gate_margin", &f->depth_gate.margin, 0.0, 2.0, "metres",
            "apart: more than this in front of the nearest or behind the farthest person depth in the window");
  s->boolean("filter.temporal", &f->temporal, "guard with the previous frame's person pixels (TemporalGuard)");
  TemporalGuard::Options& t = f->temporal_guard;
  s->number("filter.temporal_motion", &t.person_motion, 0.0, 0.5, "metres",
            "the previous frame's person pixels are dilated by this distance as seen at their depth");
  s->integer("filter.temporal_dilation", &t.dilation, 0, 80, "pixels", "... and by at least this many pixels");
  s->number("filter.temporal_margin", &t.margin, 0.0, 2.0, "metres", "a depth this close to the moved ones is guarded");
  s->integer("filter.temporal_max_age", &t.max_age, 0, 254, "frames", "frames a pixel is guarded without a box");
  s->number("filter.temporal_static_tolerance", &t.static_tolerance, 0.0, 0.5, "metres",
            "plus 1 % of the depth: a guarded pixel whose surface the previous frame gave to the map (or "
            "the guard held max_age frames) this close goes to the map, the tracker still leaves it out (0 = off)");
  s->boolean("filter.geometric", &f->geometric,
             "remove depth in front of a predicted static depth (pf2_slam: the newest keyframes'; pf2_detect: "
             "the farthest depth seen so far); off, the detector's sure candidates and pf2_slam's floor plane still "
             "count");
  s->number("filter.candidate_min_dynamic", &f->geometric_addition.candidate_min_dynamic, 0.0, 1.0, "fraction",
            "share of a detector candidate's measured pixels in front of the prediction that makes it a person "
            "(0 = candidates ignored)");
  s->number("filter.candidate_min_score", &f->geometric_addition.candidate_min_score, 0.0, 1.0, "",
            "a detector candidate at least this sure (mean mask probability) is a person without evidence "
            "(0 = evidence always needed)");
  s->number("filter.candidate_min_front", &f->geometric_addition.candidate_min_front, 0.0, 2.0, "metres",
            "... and lies at least this in front of the depth around it (0 = no such test)");
  s->integer("filter.candidate_memory", &f->geometric_addition.candidate_memory, 0, 254, "frames",
             "a confirmed candidate stays one without fresh evidence while it follows a confirmed region or person");
  s->boolean("filter.keep_static", &f->geometric_addition.keep_static,
             "depth the prediction knows as static is kept unless a mask or dynamic evidence covers it");
  s->boolean("filter.keep_behind_masks", &f->keep_static_behind_masks,
             "with keep_static, known static depth under a person's mask that lies behind their depth, or in the ring "
             "filter.mask_dilation added, is kept for the map (pf2_slam's tracker leaves it out)");
  s->boolean("filter.outside_masks_tracker_only", &f->outside_masks_tracker_only,
             "what the box, ring and temporal rules removed outside every mask (not a maskless person's box, not "
             "dynamic evidence) is kept for the map (pf2_slam's tracker leaves it out)");
}

}  // namespace

void declareFilterSettings(DualBBoxFilter::Options* options, Settings* settings) {
  paperSettings(options, settings);
  additionSettings(options, settings);
}

}  // namespace pf2
