#include "pf2/humans/human_tracker.h"

#include <algorithm>
#include <tuple>

#include "pf2/core/error.h"
#include "pf2/humans/assignment.h"

namespace pf2 {

HumanTracker::HumanTracker(const Options& options) : options_(options) {}

void HumanTracker::reset() {
  tracks_.clear();
  appearance_.clear();
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

void HumanTracker::observe(size_t track, double timestamp, const Eigen::Vector3d& centre_w,
                           const PersonAppearance& appearance) {
  tracks_[track].points.push_back({timestamp, centre_w});
  PersonAppearance& mean = appearance_[track];
  if (appearance.empty()) return;
  if (mean.size() != appearance.size()) {
    mean = appearance;
    return;
  }
  for (size_t i = 0; i < mean.size(); ++i) {
    mean[i] += static_cast<float>(options_.appearance_rate) * (appearance[i] - mean[i]);
  }
}

int HumanTracker::reidentify(double timestamp, const Eigen::Vector3d& centre_w, const PersonAppearance& appearance,
                             const std::vector<bool>& taken) const {
  if (options_.association != Association::kPredicted || options_.reid_window <= 0 || appearance.empty()) return -1;
  int best = -1;
  double best_similarity = options_.reid_similarity;
  for (size_t t = 0; t < tracks_.size(); ++t) {
    if (taken[t]) continue;  // one centre per track and frame
    const HumanTrackPoint& last = tracks_[t].points.back();
    const double unseen = timestamp - last.timestamp;
    if (unseen <= 0 || unseen > options_.reid_window) continue;
    // Where the person could have walked meanwhile.
    if ((centre_w - last.p_w).norm() > options_.gate + options_.max_speed * unseen) continue;
    const double similarity = appearanceSimilarity(appearance, appearance_[t]);
    if (similarity >= best_similarity) best_similarity = similarity, best = static_cast<int>(t);
  }
  return best;
}

std::vector<int> HumanTracker::update(double timestamp, const std::vector<Eigen::Vector3d>& centres_w,
                                      const std::vector<PersonAppearance>& appearances) {
  if (!appearances.empty() && appearances.size() != centres_w.size()) {
    throw Error("HumanTracker::update: " + std::to_string(appearances.size()) + " appearances for " +
                std::to_string(centres_w.size()) + " centres");
  }
  const auto appearance = [&](size_t c) { return appearances.empty() ? PersonAppearance() : appearances[c]; };
  const std::vector<int> live_of = options_.association == Association::kPaper
                                       ? associatePaper(centres_w)
                                       : associatePredicted(timestamp, centres_w);
  std::vector<int> ids(centres_w.size());
  std::vector<bool> seen(live_.size(), false), taken(tracks_.size(), false);
  for (size_t c = 0; c < centres_w.size(); ++c) {
    if (live_of[c] < 0) continue;
    Live& live = live_[live_of[c]];
    seen[live_of[c]] = true;
    taken[live.track] = true;
    live.missed = 0;
    observe(live.track, timestamp, centres_w[c], appearance(c));
    ids[c] = tracks_[live.track].id;
  }
  ageUnseen(seen);
  for (size_t c = 0; c < centres_w.size(); ++c) {
    if (live_of[c] >= 0) continue;
    int track = reidentify(timestamp, centres_w[c], appearance(c), taken);
    if (track < 0) {
      HumanTrack fresh;
      fresh.id = next_id_++;
      tracks_.push_back(std::move(fresh));
      appearance_.emplace_back();
      taken.push_back(false);
      track = static_cast<int>(tracks_.size()) - 1;
    }
    // A re-identified track is live again (it may still be among the live ones, unmatched).
    const auto live = std::find_if(live_.begin(), live_.end(), [&](const Live& l) { return l.track == static_cast<size_t>(track); });
    if (live == live_.end()) {
      live_.push_back({static_cast<size_t>(track), 0});
    } else {
      live->missed = 0;
    }
    taken[track] = true;
    observe(track, timestamp, centres_w[c], appearance(c));
    ids[c] = tracks_[track].id;
  }
  return ids;
}

// Ages the live tracks without a centre this frame and drops those past their limit (the paper
// keeps none unseen).
void HumanTracker::ageUnseen(const std::vector<bool>& seen) {
  const int max_missed = options_.association == Association::kPaper ? 0 : options_.max_missed;
  std::vector<Live> kept;
  for (size_t l = 0; l < live_.size(); ++l) {
    if (!seen[l]) ++live_[l].missed;
    if (live_[l].missed <= max_missed) kept.push_back(live_[l]);
  }
  live_ = std::move(kept);
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
