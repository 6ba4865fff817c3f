#include "pf2/humans/human_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>

#include "pf2/core/error.h"
#include "pf2/humans/assignment.h"

namespace pf2 {

HumanTracker::HumanTracker(const Options& options) : options_(options) {}

void HumanTracker::reset() {
  tracks_.clear();
  appearance_.clear();
  first_camera_w_.clear();
  live_.clear();
  aliases_.clear();
  next_id_ = 1;
}

HumanTracker::TrackLine HumanTracker::fitLine(const HumanTrack& track) const {
  const std::vector<HumanTrackPoint>& points = track.points;
  const HumanTrackPoint& last = points.back();
  // A straight line fitted (least squares) to the centres of the last velocity_window seconds,
  // which predict() extrapolates: a centre that jumps for a frame or two (a person entering the
  // view beside this one, their boxes merging) moves the line by its share of the window, not the
  // whole prediction, and box jitter averages out.
  double sum_t = 0.0, sum_tt = 0.0;
  Eigen::Vector3d sum_p = Eigen::Vector3d::Zero(), sum_tp = Eigen::Vector3d::Zero();
  int n = 0;
  for (auto it = points.rbegin(); it != points.rend() && last.timestamp - it->timestamp <= options_.velocity_window; ++it) {
    const double t = it->timestamp - last.timestamp;  // <= 0: well conditioned
    sum_t += t;
    sum_tt += t * t;
    sum_p += it->p_w;
    sum_tp += t * it->p_w;
    ++n;
  }
  const double variance = sum_tt - sum_t * sum_t / n;
  if (n < 2 || variance <= 1e-9) return {last.p_w, Eigen::Vector3d::Zero(), n};
  Eigen::Vector3d velocity = (sum_tp - sum_t * sum_p / n) / variance;
  const double speed = velocity.norm();
  if (speed > options_.max_speed) velocity *= options_.max_speed / speed;
  return {(sum_p - velocity * sum_t) / n, velocity, n};  // at_last: the line at the last centre's time
}

Eigen::Vector3d HumanTracker::predict(const Live& live, double timestamp, int* centres_used, double* speed_out) const {
  const HumanTrack& track = tracks_[live.track];
  const TrackLine line = fitLine(track);
  if (centres_used != nullptr) *centres_used = line.centres;
  if (speed_out != nullptr) *speed_out = line.velocity.norm();
  return line.at_last + line.velocity * (timestamp - track.points.back().timestamp);
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

std::vector<int> HumanTracker::associatePredicted(double timestamp, const std::vector<Eigen::Vector3d>& centres_w,
                                                  const std::vector<PersonAppearance>& appearances) const {
  // Rows: centres; columns: live tracks. A pair is allowed when its distance, as a share of the
  // track's gate, plus the appearance's dissimilarity (where both are known: of two people close
  // together, each track keeps the one who looks like it) is at most 1. Allowed pairs cost their
  // distance as a share of the base gate, the same for every track, plus that dissimilarity: a
  // track unseen for longer has a wider gate but no claim on a centre nearer to another's
  // prediction (by its own gate's share it would win every close call).
  double max_cost = 1.0;  // the largest allowed pair's cost
  std::vector<std::vector<double>> cost(centres_w.size(), std::vector<double>(live_.size()));
  for (size_t l = 0; l < live_.size(); ++l) {
    int centres_used = 1;
    double speed = 0.0;
    const Eigen::Vector3d predicted = predict(live_[l], timestamp, &centres_used, &speed);
    const double unseen = timestamp - tracks_[live_[l].track].points.back().timestamp;
    // A prediction made of n centres carries their noise / sqrt(n): the centre it is compared with
    // may lie further from it when n is small (a track just seen again after a gap rests on one
    // centre, which may itself be off).
    const double growth = speed < options_.still_speed ? options_.still_gate_growth : options_.gate_growth;
    const double gate = options_.gate * std::sqrt(1.0 + 1.0 / centres_used) + growth * std::max(0.0, unseen);
    const PersonAppearance& track_appearance = appearance_[live_[l].track];
    for (size_t c = 0; c < centres_w.size(); ++c) {
      const double distance = (centres_w[c] - predicted).norm();
      double dissimilarity = 0.0;
      if (c < appearances.size() && !appearances[c].empty() && track_appearance.size() == appearances[c].size()) {
        dissimilarity = options_.appearance_weight * (1.0 - appearanceSimilarity(appearances[c], track_appearance));
      }
      const bool allowed = distance / gate + dissimilarity <= 1.0;
      cost[c][l] = allowed ? distance / options_.gate + dissimilarity : std::numeric_limits<double>::infinity();
      if (allowed) max_cost = std::max(max_cost, cost[c][l]);
    }
  }
  return solveAssignment(cost, max_cost);  // pairs above max_cost (the infinite ones) are never matched
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
  blendAppearance(appearance, &mean);
}

void HumanTracker::blendAppearance(const PersonAppearance& view, PersonAppearance* mean) const {
  const float rate = static_cast<float>(options_.appearance_rate);
  for (size_t i = 0; i < mean->size(); ++i) (*mean)[i] += rate * (view[i] - (*mean)[i]);
}

int HumanTracker::reidentify(size_t fresh) const {
  if (options_.association != Association::kPredicted || options_.reid_window <= 0) return -1;
  const PersonAppearance& appearance = appearance_[fresh];
  if (appearance.empty()) return -1;
  const HumanTrackPoint& first = tracks_[fresh].points.front();
  int best = -1;
  double best_score = -std::numeric_limits<double>::infinity();
  for (size_t t = 0; t < tracks_.size(); ++t) {
    // A track that never had reid_after centres was a stray one, no person to come back.
    if (t == fresh || !confirmed(t)) continue;
    const HumanTrackPoint& last = tracks_[t].points.back();
    // Seen while the new track was: someone else.
    const double unseen = first.timestamp - last.timestamp;
    if (unseen <= 0 || unseen > options_.reid_window) continue;
    const double speed = impliedSpeed(tracks_[t], first);
    if (speed > options_.max_speed || !reachable(tracks_[t], first)) continue;
    const double similarity = appearanceSimilarity(appearance, appearance_[t]);
    // Speed 0: the new track began within the gate of one of the lost track's last centres.
    const bool stayed = speed == 0.0 && unseen <= options_.reid_near_time;
    const double needed = stayed ? std::min(options_.reid_similarity, options_.reid_near_similarity)
                                 : options_.reid_similarity;
    if (similarity < needed || occludedBy(tracks_[t], fresh)) continue;
    // Of the lost tracks that look alike, the one its person need not have hurried from.
    const double score = similarity - options_.reid_speed_cost * speed;
    if (score > best_score) best_score = score, best = static_cast<int>(t);
  }
  return best;
}

// The speed (m/s) at which the person of `old` must have walked to `first` (a later centre) while
// unseen, beyond the gate: the least over old's last reid_after centres, not only the last one. A
// box that merged two people puts a track's last centre on the other person (at their depth),
// metres from where this one was.
double HumanTracker::impliedSpeed(const HumanTrack& old, const HumanTrackPoint& first) const {
  const size_t considered = std::min(old.points.size(), confirmedCentres());
  double least = std::numeric_limits<double>::infinity();
  for (size_t k = old.points.size() - considered; k < old.points.size(); ++k) {
    const HumanTrackPoint& from = old.points[k];
    const double beyond_gate = std::max(0.0, (first.p_w - from.p_w).norm() - options_.gate);
    const double elapsed = first.timestamp - from.timestamp;
    if (beyond_gate == 0.0) return 0.0;
    if (elapsed > 0.0) least = std::min(least, beyond_gate / elapsed);
  }
  return least;
}

bool HumanTracker::reachable(const HumanTrack& old, const HumanTrackPoint& first) const {
  const double a = options_.max_acceleration, v_max = options_.max_speed;
  if (!(a > 0.0)) return true;
  const double v0 = fitLine(old).velocity.norm();  // at most max_speed
  const double speeding_up = (v_max - v0) / a;  // seconds until max_speed
  const size_t considered = std::min(old.points.size(), confirmedCentres());
  for (size_t k = old.points.size() - considered; k < old.points.size(); ++k) {
    const HumanTrackPoint& from = old.points[k];
    const double t = std::max(0.0, first.timestamp - from.timestamp);
    // From v0, speeding up at a in any direction, then at max_speed: the farthest they get.
    const double reach = t < speeding_up ? v0 * t + 0.5 * a * t * t
                                         : v0 * speeding_up + 0.5 * a * speeding_up * speeding_up + v_max * (t - speeding_up);
    if ((first.p_w - from.p_w).norm() <= options_.gate + reach) return true;
  }
  return false;
}

// A person's half width and their centre's noise: a centre this near the line of sight to another
// stands in front of them.
constexpr double kLineOfSightRadius = 0.3;  // metres

bool HumanTracker::occludedBy(const HumanTrack& old, size_t fresh) const {
  const std::optional<Eigen::Vector3d>& camera_w = first_camera_w_[fresh];
  const HumanTrackPoint& first = tracks_[fresh].points.front();
  if (!(options_.occluder_margin > 0.0) || !camera_w ||
      first.timestamp - old.points.back().timestamp > options_.occluder_window) {
    return false;
  }
  const Eigen::Vector3d to_first = first.p_w - *camera_w;
  const size_t considered = std::min(old.points.size(), confirmedCentres());
  for (size_t k = old.points.size() - considered; k < old.points.size(); ++k) {
    const Eigen::Vector3d to_old = old.points[k].p_w - *camera_w;
    const double range = to_old.norm();
    if (!(range > 0.0)) continue;
    const Eigen::Vector3d ray = to_old / range;
    const double along = to_first.dot(ray);
    if (along > 0.0 && along < range - options_.occluder_margin &&
        (to_first - along * ray).norm() < kLineOfSightRadius) {
      return true;
    }
  }
  return false;
}

// The new track's centres become the old track's (all of them later than the old one's last),
// its appearance is taken in, its id becomes an alias, and the old track is the live one.
void HumanTracker::merge(size_t fresh, size_t old) {
  HumanTrack& track = tracks_[old];
  const std::vector<HumanTrackPoint>& points = tracks_[fresh].points;
  track.points.insert(track.points.end(), points.begin(), points.end());
  if (appearance_[old].size() == appearance_[fresh].size()) blendAppearance(appearance_[fresh], &appearance_[old]);
  aliases_[tracks_[fresh].id] = track.id;
  // The old track may still be live, unseen: one live entry, the new track's, now for it.
  live_.erase(std::remove_if(live_.begin(), live_.end(), [&](const Live& l) { return l.track == old; }), live_.end());
  tracks_.erase(tracks_.begin() + static_cast<std::ptrdiff_t>(fresh));
  appearance_.erase(appearance_.begin() + static_cast<std::ptrdiff_t>(fresh));
  first_camera_w_.erase(first_camera_w_.begin() + static_cast<std::ptrdiff_t>(fresh));
  for (Live& l : live_) {
    if (l.track == fresh) l.track = old;
    else if (l.track > fresh) --l.track;
  }
}

bool HumanTracker::reidentificationDue(const HumanTrack& track, double timestamp) const {
  if (track.points.back().timestamp != timestamp) return false;
  size_t centres = confirmedCentres();
  for (int check = 0; check < options_.reid_checks; ++check, centres *= 2) {
    if (track.points.size() == centres) return true;
  }
  return false;
}

void HumanTracker::reidentifyNewTracks(double timestamp, std::vector<int>* ids) {
  // The tracks that got their reid_after-th (2 x, 4 x ... reid_after-th) centre in this frame.
  std::vector<int> due;
  for (const Live& live : live_) {
    const HumanTrack& track = tracks_[live.track];
    if (reidentificationDue(track, timestamp)) due.push_back(track.id);
  }
  for (const int fresh_id : due) {
    const size_t fresh = static_cast<size_t>(
        std::find_if(tracks_.begin(), tracks_.end(), [&](const HumanTrack& t) { return t.id == fresh_id; }) -
        tracks_.begin());
    const int old = reidentify(fresh);
    if (old < 0) continue;
    const int old_id = tracks_[old].id;
    merge(fresh, static_cast<size_t>(old));
    std::replace(ids->begin(), ids->end(), fresh_id, old_id);
  }
}

bool HumanTracker::crowded(size_t taker, const Eigen::Vector3d& centre_w,
                           const std::vector<Eigen::Vector3d>& predicted) const {
  for (size_t l = 0; l < predicted.size(); ++l) {
    if (l != taker && (predicted[l] - centre_w).norm() < options_.appearance_crowd) return true;
  }
  return false;
}

size_t HumanTracker::confirmedCentres() const { return static_cast<size_t>(std::max(1, options_.reid_after)); }

bool HumanTracker::confirmed(size_t track) const { return tracks_[track].points.size() >= confirmedCentres(); }

int HumanTracker::resolvedId(int id) const {
  for (auto it = aliases_.find(id); it != aliases_.end(); it = aliases_.find(id)) id = it->second;
  return id;
}

std::vector<int> HumanTracker::update(double timestamp, const std::vector<Eigen::Vector3d>& centres_w,
                                      const std::vector<PersonAppearance>& appearances,
                                      const std::optional<Eigen::Vector3d>& camera_w) {
  if (!appearances.empty() && appearances.size() != centres_w.size()) {
    throw Error("HumanTracker::update: " + std::to_string(appearances.size()) + " appearances for " +
                std::to_string(centres_w.size()) + " centres");
  }
  const auto appearance = [&](size_t c) { return appearances.empty() ? PersonAppearance() : appearances[c]; };
  const std::vector<int> live_of = options_.association == Association::kPaper
                                       ? associatePaper(centres_w)
                                       : associatePredicted(timestamp, centres_w, appearances);
  std::vector<int> ids(centres_w.size());
  std::vector<bool> seen(live_.size(), false);
  std::vector<Eigen::Vector3d> predicted;  // before any track takes this frame's centre
  for (const Live& live : live_) predicted.push_back(predict(live, timestamp));
  for (size_t c = 0; c < centres_w.size(); ++c) {
    if (live_of[c] < 0) continue;
    Live& live = live_[live_of[c]];
    seen[live_of[c]] = true;
    live.missed = 0;
    const bool mixed = crowded(static_cast<size_t>(live_of[c]), centres_w[c], predicted);
    observe(live.track, timestamp, centres_w[c], mixed ? PersonAppearance() : appearance(c));
    ids[c] = tracks_[live.track].id;
  }
  ageUnseen(seen);
  // Other centres start new tracks (compared with the lost ones once they have reid_after centres).
  for (size_t c = 0; c < centres_w.size(); ++c) {
    if (live_of[c] >= 0) continue;
    HumanTrack fresh;
    fresh.id = next_id_++;
    tracks_.push_back(std::move(fresh));
    appearance_.emplace_back();
    first_camera_w_.push_back(camera_w);
    live_.push_back({tracks_.size() - 1, 0});
    observe(tracks_.size() - 1, timestamp, centres_w[c], appearance(c));
    ids[c] = tracks_.back().id;
  }
  reidentifyNewTracks(timestamp, &ids);
  return ids;
}

// Ages the live tracks without a centre this frame and drops those past their limit (the paper
// keeps none unseen).
void HumanTracker::ageUnseen(const std::vector<bool>& seen) {
  const int max_missed = options_.association == Association::kPaper ? 0 : options_.max_missed;
  // A track with fewer than reid_after centres is not yet a person (a centre split off another's,
  // a false detection): it ends at its first missed frame instead of taking a centre later.
  std::vector<Live> kept;
  for (size_t l = 0; l < live_.size(); ++l) {
    if (!seen[l]) ++live_[l].missed;
    const int allowed = confirmed(live_[l].track) ? max_missed : 0;
    if (live_[l].missed <= allowed) kept.push_back(live_[l]);
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
