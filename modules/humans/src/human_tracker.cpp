#include "pf2/humans/human_tracker.h"

#include <algorithm>
#include <tuple>

#include "pf2/core/error.h"
#include "pf2/humans/assignment.h"

namespace pf2 {

HumanTracker::HumanTracker(const Options& options) : options_(options) {}

void HumanTracker::reset() {
  tracks_.clear();
  live_.clear();
  next_id_ = 1;
}

Eigen::Vector3d HumanTracker::predict(const Live& live, double timestamp) const {
  const std::vector<HumanTrackPoint>& points = tracks_[live.track].points;
  const HumanTrackPoint& last = points.back();
  // Velocity from the oldest point inside the window to the newest: one long baseline instead of
  // frame-to-frame differences, which box jitter makes noisy.
  const HumanTrackPoint* oldest = &last;
  for (auto it = points.rbegin(); it != points.rend() && last.timestamp - it->timestamp <= options_.velocity_window; ++it) {
    oldest = &*it;
  }
  const double span = last.timestamp - oldest->timestamp;
  if (span <= 0.0) return last.p_w;
  Eigen::Vector3d velocity = (last.p_w - oldest->p_w) / span;
  const double speed = velocity.norm();
  if (speed > options_.max_speed) velocity *= options_.max_speed / speed;
  return last.p_w + velocity * (timestamp - last.timestamp);
}

std::vector<int> HumanTracker::associatePaper(const std::vector<Eigen::Vector3d>& centres_w) const {
  // Only tracks seen in the previous frame take part; closest pairs first, no distance limit.
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (size_t l = 0; l < live_.size(); ++l) {
    if (live_[l].missed > 0) continue;
    const Eigen::Vector3d& previous = tracks_[live_[l].track].points.back().p_w;
    for (size_t c = 0; c < centres_w.size(); ++c) pairs.emplace_back((centres_w[c] - previous).norm(), c, l);
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<int> live_of(centres_w.size(), -1);
  std::vector<bool> taken(live_.size(), false);
  for (const auto& [distance, c, l] : pairs) {
    if (live_of[c] >= 0 || taken[l]) continue;
    live_of[c] = static_cast<int>(l);
    taken[l] = true;
  }
  return live_of;
}

std::vector<int> HumanTracker::associatePredicted(double timestamp,
                                                  const std::vector<Eigen::Vector3d>& centres_w) const {
  // Rows: centres; columns: live tracks; cost: distance to the prediction, normalised by the
  // track's gate so that one threshold (1) applies to tracks unseen for different times.
  std::vector<std::vector<double>> cost(centres_w.size(), std::vector<double>(live_.size()));
  for (size_t l = 0; l < live_.size(); ++l) {
    const Eigen::Vector3d predicted = predict(live_[l], timestamp);
    const double unseen = timestamp - tracks_[live_[l].track].points.back().timestamp;
    const double gate = options_.gate + options_.gate_growth * std::max(0.0, unseen);
    for (size_t c = 0; c < centres_w.size(); ++c) cost[c][l] = (centres_w[c] - predicted).norm() / gate;
  }
  return solveAssignment(cost, 1.0);
}

std::vector<int> HumanTracker::update(double timestamp, const std::vector<Eigen::Vector3d>& centres_w) {
  const std::vector<int> live_of = options_.association == Association::kPaper
                                       ? associatePaper(centres_w)
                                       : associatePredicted(timestamp, centres_w);
  std::vector<int> ids(centres_w.size());
  std::vector<bool> seen(live_.size(), false);
  for (size_t c = 0; c < centres_w.size(); ++c) {
    if (live_of[c] >= 0) {
      Live& live = live_[live_of[c]];
      seen[live_of[c]] = true;
      live.missed = 0;
      tracks_[live.track].points.push_back({timestamp, centres_w[c]});
      ids[c] = tracks_[live.track].id;
    }
  }
  // Age the unseen tracks and drop those past their limit (the paper keeps none unseen).
  const int max_missed = options_.association == Association::kPaper ? 0 : options_.max_missed;
  std::vector<Live> kept;
  for (size_t l = 0; l < live_.size(); ++l) {
    if (!seen[l]) ++live_[l].missed;
    if (live_[l].missed <= max_missed) kept.push_back(live_[l]);
  }
  live_ = std::move(kept);
  for (size_t c = 0; c < centres_w.size(); ++c) {
    if (live_of[c] >= 0) continue;
    HumanTrack track;
    track.id = next_id_++;
    track.points.push_back({timestamp, centres_w[c]});
    tracks_.push_back(std::move(track));
    live_.push_back({tracks_.size() - 1, 0});
    ids[c] = tracks_.back().id;
  }
  return ids;
}

HumanTracker::Association humanAssociationFromName(const std::string& name) {
  if (name == "paper") return HumanTracker::Association::kPaper;
  if (name == "predicted") return HumanTracker::Association::kPredicted;
  throw Error("unknown human association '" + name + "' (expected paper or predicted)");
}

const char* toString(HumanTracker::Association association) {
  return association == HumanTracker::Association::kPaper ? "paper" : "predicted";
}

}  // namespace pf2
