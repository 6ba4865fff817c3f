#include "pf2/eval/human_metrics.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <optional>

#include "pf2/humans/assignment.h"

namespace pf2 {

namespace {

struct Sample {
  int id;
  Eigen::Vector3d p_w;
};

struct Match {
  int track;
  Eigen::Vector3d offset;  // estimate - truth
};

// One frame's matching, as CLEAR MOT defines it: a person keeps the track matched to them in the
// previous frame while that track's estimate lies within match_distance of them, even when
// another estimate is nearer (two people passing each other must not count as two switches); the
// other people and estimates are matched by minimum total distance. Returns, per truth, the index
// of its estimate or -1.
std::vector<int> matchFrame(const std::vector<Sample>& truths, const std::vector<Sample>& estimates,
                            const std::map<int, int>& last_track, double match_distance) {
  std::vector<int> match(truths.size(), -1);
  std::vector<bool> taken(estimates.size(), false);
  for (size_t g = 0; g < truths.size(); ++g) {
    const auto last = last_track.find(truths[g].id);
    if (last == last_track.end()) continue;
    for (size_t e = 0; e < estimates.size(); ++e) {
      if (!taken[e] && estimates[e].id == last->second &&
          (estimates[e].p_w - truths[g].p_w).norm() <= match_distance) {
        match[g] = static_cast<int>(e);
        taken[e] = true;
        break;
      }
    }
  }
  std::vector<size_t> free_truths, free_estimates;
  for (size_t g = 0; g < truths.size(); ++g) {
    if (match[g] < 0) free_truths.push_back(g);
  }
  for (size_t e = 0; e < estimates.size(); ++e) {
    if (!taken[e]) free_estimates.push_back(e);
  }
  std::vector<std::vector<double>> cost(free_truths.size(), std::vector<double>(free_estimates.size()));
  for (size_t g = 0; g < free_truths.size(); ++g) {
    for (size_t e = 0; e < free_estimates.size(); ++e) {
      cost[g][e] = (estimates[free_estimates[e]].p_w - truths[free_truths[g]].p_w).norm();
    }
  }
  const std::vector<int> free_match = solveAssignment(cost, match_distance);
  for (size_t g = 0; g < free_truths.size(); ++g) {
    if (free_match[g] >= 0) match[free_truths[g]] = static_cast<int>(free_estimates[free_match[g]]);
  }
  return match;
}

}  // namespace

HumanMetrics evaluateHumanTracks(const std::vector<HumanTrack>& ground_truth,
                                 const std::vector<HumanTrack>& estimate,
                                 const HumanMetricsOptions& options) {
  // Frames are the ground truth's stamps; each estimate point joins the nearest one in time.
  std::map<double, std::vector<Sample>> truth_at, estimate_at;
  for (const HumanTrack& track : ground_truth) {
    for (const HumanTrackPoint& point : track.points) truth_at[point.timestamp].push_back({track.id, point.p_w});
  }
  HumanMetrics result;
  for (const HumanTrack& track : estimate) {
    ++result.tracks;
    for (const HumanTrackPoint& point : track.points) {
      ++result.estimates;
      auto after = truth_at.lower_bound(point.timestamp);
      auto nearest = after;
      if (after != truth_at.begin()) {
        const auto before = std::prev(after);
        if (after == truth_at.end() || point.timestamp - before->first < after->first - point.timestamp) {
          nearest = before;
        }
      }
      if (nearest == truth_at.end() || std::abs(nearest->first - point.timestamp) > options.max_time_difference) {
        ++result.unmatched_estimates;
        continue;
      }
      estimate_at[nearest->first].push_back({track.id, point.p_w});
    }
  }

  // Per ground-truth person, in time order: the match of each of their frames, if any.
  std::map<int, std::vector<std::optional<Match>>> history;
  std::map<int, int> last_track;  // ground-truth id -> track matched in the previous frame
  for (const auto& [stamp, truths] : truth_at) {
    const std::vector<Sample>& estimates = estimate_at[stamp];
    const std::vector<int> match = matchFrame(truths, estimates, last_track, options.match_distance);
    int matched_here = 0;
    last_track.clear();
    for (size_t g = 0; g < truths.size(); ++g) {
      std::optional<Match> m;
      if (match[g] >= 0) {
        m = Match{estimates[match[g]].id, estimates[match[g]].p_w - truths[g].p_w};
        last_track[truths[g].id] = m->track;
        ++matched_here;
      }
      history[truths[g].id].push_back(m);
    }
    result.unmatched_estimates += static_cast<int>(estimates.size()) - matched_here;
  }

  std::vector<double> all_errors, all_errors_without_offset;
  for (const auto& [gt_id, matches] : history) {
    HumanPersonMetrics person;
    person.gt_id = gt_id;
    person.frames = static_cast<int>(matches.size());
    std::map<int, int> frames_of_track;
    std::vector<double> errors;
    int last_track = -1;
    bool matched_before = false, gap = false;
    for (const std::optional<Match>& m : matches) {
      if (!m) {
        gap = matched_before;
        continue;
      }
      ++person.matched;
      if (last_track >= 0 && m->track != last_track) ++person.id_switches;
      if (gap) ++person.fragmentations;
      last_track = m->track;
      matched_before = true;
      gap = false;
      ++frames_of_track[m->track];
      person.mean_offset += m->offset;
      errors.push_back(m->offset.norm());
    }
    if (person.matched > 0) {
      person.mean_offset /= person.matched;
      // The majority track; the lowest id wins a tie, so the result does not depend on map order.
      int best = 0;
      for (const auto& [track, count] : frames_of_track) {
        if (count > best) {
          best = count;
          person.track = track;
        }
      }
    }
    std::vector<double> errors_without_offset;
    for (const std::optional<Match>& m : matches) {
      if (m) errors_without_offset.push_back((m->offset - person.mean_offset).norm());
    }
    person.error = computeErrorStatistics(errors);
    person.error_without_offset = computeErrorStatistics(errors_without_offset);
    all_errors.insert(all_errors.end(), errors.begin(), errors.end());
    all_errors_without_offset.insert(all_errors_without_offset.end(), errors_without_offset.begin(),
                                     errors_without_offset.end());
    result.frames += person.frames;
    result.matched += person.matched;
    result.id_switches += person.id_switches;
    result.fragmentations += person.fragmentations;
    result.people.push_back(person);
  }
  result.recall = result.frames > 0 ? static_cast<double>(result.matched) / result.frames : 0.0;
  result.error = computeErrorStatistics(all_errors);
  result.error_without_offset = computeErrorStatistics(all_errors_without_offset);
  return result;
}

}  // namespace pf2
