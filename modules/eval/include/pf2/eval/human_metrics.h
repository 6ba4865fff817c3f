#pragma once
// How far estimated human trajectories are from the ground truth, and how well they keep each
// person's identity (CLEAR-MOT style: Bernardin & Stiefelhagen 2008; fragmentations as Li, Huang
// & Nevatia 2009 count them).
//
// Per ground-truth frame (a timestamp of the ground truth), the estimated centres of that frame
// (stamps within max_time_difference) are matched to the ground-truth positions as CLEAR MOT does:
// a person keeps last frame's track while its centre lies within match_distance of them; the rest
// are matched by minimum total distance, pairs farther than match_distance excluded. Then, per
// ground-truth person:
//   matched / frames     recall of person-frames;
//   id switches          the matched track id differs from the one matched last time;
//   fragmentations       the person is matched again after frames of theirs without a match;
//   track                the track id matched most often (majority);
//   error                distance of each match; mean_offset the mean (estimate - truth) vector;
//                        error_without_offset the distance after taking mean_offset off, which
//                        separates a constant offset (our centre is not the pelvis) from scatter.
// Both inputs must be in the same world frame; the ground truth should hold only the
// person-frames that count (e.g. people in view, frames of the run).
#include <vector>

#include <Eigen/Core>

#include "pf2/eval/error_statistics.h"
#include "pf2/humans/human_track.h"

namespace pf2 {

struct HumanMetricsOptions {
  double match_distance = 0.5;        // metres: farther pairs are no match
  double max_time_difference = 0.02;  // seconds between an estimate's stamp and its frame's
};

struct HumanPersonMetrics {
  int gt_id = 0;
  int track = -1;          // majority track id; -1 when never matched
  int frames = 0;          // ground-truth frames of this person
  int matched = 0;
  int id_switches = 0;
  int fragmentations = 0;
  ErrorStatistics error;                // metres, over the matched frames
  Eigen::Vector3d mean_offset = Eigen::Vector3d::Zero();  // metres, world frame
  ErrorStatistics error_without_offset;
};

struct HumanMetrics {
  std::vector<HumanPersonMetrics> people;  // in ground-truth id order
  int frames = 0;            // ground-truth person-frames
  int matched = 0;
  int estimates = 0;         // estimated points
  int unmatched_estimates = 0;  // estimated points matched to nobody (false positives)
  int tracks = 0;            // estimated track ids
  int id_switches = 0;
  int fragmentations = 0;
  double recall = 0;         // matched / frames
  ErrorStatistics error;     // over all matches
  ErrorStatistics error_without_offset;  // each match less its person's mean offset
};

// Thread safe.
HumanMetrics evaluateHumanTracks(const std::vector<HumanTrack>& ground_truth,
                                 const std::vector<HumanTrack>& estimate,
                                 const HumanMetricsOptions& options = HumanMetricsOptions());

}  // namespace pf2
