#pragma once
// HumanTracker: gives each frame's person centres (world frame, eq. 3) the ids of the people they
// belong to, so that each person's centres form one trajectory (paper §III-B).
//
// Two associations, chosen in Options:
//   kPaper     — the paper's heuristic: each centre takes the id of the closest centre of the
//                previous frame (closest pairs first, each id once); a centre with no previous
//                one left starts a new id. No memory beyond one frame: a person missed for a
//                single frame comes back under a new id, and two people passing close to each
//                other swap ids when each is nearer to where the other was.
//   kPredicted — ours: each track predicts where its person is now from a constant velocity
//                (a line fitted to its centres of the last velocity_window seconds); centres and
//                tracks are matched by minimum total distance (Hungarian) within a gate that
//                widens the longer a track has been unseen (more slowly for a person last seen
//                standing: still_speed) and the fewer centres its prediction rests on
//                (gate x sqrt(1 + 1/n), n centres in velocity_window); tracks
//                survive max_missed frames without a centre, so a person hidden for a moment
//                keeps their id; a centre no live track takes is first compared with the
//                tracks lost or unmatched within the last reid_window seconds, by appearance
//                (colour histogram) and a reachable position (from any of its last reid_after
//                centres: its last one may have come from a box that merged two people; from the
//                speed the track was last seen at, speeding up by at most max_acceleration): of
//                those at reid_similarity or more (reid_near_similarity for a person back
//                within reid_near_time where they were lost), the one scoring highest
//                (similarity less reid_speed_cost per m/s its person must have walked while
//                unseen) takes it under its old id. A lost track is not offered to a new one
//                that first stood in front of where it was last seen, on the camera's line of
//                sight, soon after it was lost (occluder_margin): that is the person who hid
//                them.
//                The comparison waits until the new track has reid_after centres (and is
//                made again at 2 x, 4 x ... reid_after, reid_checks times in all): a stray
//                centre that lasts a frame or two (a person's part split off, a false
//                detection) cannot take a lost person's id, and the new track's appearance is
//                a mean over several views. A new track merged into an old one keeps its id
//                as an alias: resolvedId() gives the old id for the frames it was reported under.
//                A track with fewer than reid_after centres ends at its first missed frame (as
//                SORT's tentative tracks): a split-off centre's track must not live on to take
//                a person's centre later.
// Other unmatched centres start new tracks; ids are 1, 2, 3, ... in order of appearance, never reused.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "pf2/humans/human_track.h"
#include "pf2/humans/person_appearance.h"

namespace pf2 {

class HumanTracker {
 public:
  enum class Association { kPaper, kPredicted };

  struct Options {
    Association association = Association::kPredicted;
    // --- kPredicted only ---
    // Metres between a track's prediction and a centre it may take (for a prediction made of many
    // centres; one made of n is trusted less, x sqrt(1 + 1/n)). 0.5: of the centres the
    // tracks took on 15 pf2_synth runs, those of the track's own person lay at most 0.30 m from
    // its prediction in 99 % of frames and 0.46 m in 99.9 % (max 0.65); at 1 m the track of a
    // person hidden by someone walking in front of them moved onto the walker, 0.1-0.2 m a frame
    // (repeatable runs of seeds 1-5: identity switches 7 -> 4; 0.4 m split tracks: 46 -> 48).
    double gate = 0.5;
    double gate_growth = 1.0;       // metres per second unseen added to the gate (the person may
                                    // have turned or stopped while hidden)
    // A person last seen standing (the speed of their track's fitted line under still_speed, m/s)
    // is looked for within a gate that grows by still_gate_growth (m/s) instead while unseen: a
    // seated or standing person missed by the detector for a few tenths of a second is mostly
    // still there, and a gate grown at walking pace let their track take someone else who came
    // into view 0.7-1.2 m away (pf2_synth halfsphere seed 23: two people's tracks swapped).
    // still_speed 0 = off. Repeatable runs, docs/BENCHMARKS.md "Bodies in the map".
    double still_speed = 0.3;        // m/s, [0, 10]
    double still_gate_growth = 0.3;  // m/s, [0, 10]
    // A new track is re-identified as a lost one only where its person could have walked while
    // unseen: from the speed of the lost track's fitted line, speeding up by at most this much
    // (m/s², up to max_speed) in any direction, beyond the gate. max_speed alone let a standing
    // person missed for a third of a second give their id to someone 1.2 m behind them who came
    // into view (pf2_synth halfsphere seed 19). People start walking at about 1 m/s². 0 = off;
    // in [0, 20].
    double max_acceleration = 1.0;
    int max_missed = 30;            // frames a track lives without a centre (1 s at 30 Hz)
    double velocity_window = 0.5;   // seconds of the track's past its velocity is measured over
                                    // (longer: less noise from box jitter, slower to follow turns)
    double max_speed = 2.5;         // m/s: the velocity is clamped to this (a walking person)
    double reid_window = 10.0;      // s: a track unseen this long can still be re-identified (0 = never)
    // Appearance similarity (Bhattacharyya coefficient) needed, 0..1. 0.70: on pf2_synth seeds
    // 6-10 people back in view scored 0.69-0.74 against their own lost track (seen partly at the
    // border or close to the lens before they left); other people's tracks within reach scored
    // 0.70-0.75 only where the person's own track scored higher or had been given this person's
    // detection at a wrong depth (repeatable runs, seeds 1-10: switches 11 -> 9, tracks 94 -> 91
    // for 90 people; seeds 1-5 unchanged).
    double reid_similarity = 0.70;
    // Similarity taken off a lost track's claim on a new one per m/s its person must have walked
    // (beyond the gate) while unseen: of the lost tracks that look alike (each at reid_similarity
    // or more), the one the person need not have hurried from re-identifies them. 0 = the most
    // similar one.
    double reid_speed_cost = 0.15;
    // A lost track its person need not have moved from (the new track's first centre within the
    // gate of one of its last reid_after centres), unseen at most reid_near_time seconds, takes the
    // new track at this lower similarity, in [0, 1]: over a short absence where they were, the
    // position says more than the colours of a person back half hidden, turned or risen from a
    // chair (pf2_synth: a seated person hidden 1.2 s by a walker scored 0.62-0.66 against their
    // own track). Repeatable runs, seeds 1-5 and 16-20: identity switches 9 -> 8, tracks 93 -> 92;
    // held-out seeds 26-30 and 41-45: 8 -> 6, 94 -> 93; no run worse in any target.
    double reid_near_similarity = 0.55;
    double reid_near_time = 2.0;    // seconds (see reid_near_similarity), [0, 60]; 0 = off
    int reid_after = 5;             // centres a new track has before it is compared with lost
                                    // tracks (1 = at first sight); fewer: it ends when missed
    // Comparisons of a new track with the lost ones: at reid_after centres, then again at 2 x, 4 x
    // ... reid_after while it has not been re-identified (1 = once). A person coming back into
    // view is first seen in part (at the border, close to the lens), and their colours over the
    // first few views may not yet be those of the whole person.
    int reid_checks = 3;
    double appearance_rate = 0.2;   // weight of a new view in a track's appearance (running mean)
    // Added to the association cost (distance / gate; at most 1 matches) per unit of appearance
    // dissimilarity (1 - similarity): of two people close together, each track keeps the one who
    // looks like it. 0 = position only.
    double appearance_weight = 0.5;
    // Metres: a centre this near the prediction of another live track leaves its own track's
    // appearance as it was (a detection of two people close together holds both of them, and a
    // track that learned that mix re-identifies the wrong person when they part). Repeatable
    // runs of pf2_synth seeds 1-5: one identity switch fewer (halfsphere seed 2), nothing else
    // changed. 0 = every centre's appearance is learned.
    double appearance_crowd = 0.6;
    // Metres: a new track whose first centre stands this much nearer the camera than one of a lost
    // track's last reid_after centres, on the line of sight to it, is not re-identified as that
    // track when it was lost at most occluder_window seconds before: it is the person who walked
    // in front and hid them (whose pixels also pulled the hidden one's last centres towards
    // them). Without it, on pf2_synth a seated or standing person hidden by someone entering the
    // view gave their id to the newcomer and came back under a new one. 0 = off. Needs the
    // camera's position (update()).
    double occluder_margin = 0.3;
    double occluder_window = 1.0;  // seconds (see occluder_margin)
  };

  HumanTracker() : HumanTracker(Options()) {}
  explicit HumanTracker(const Options& options);

  // Associates the centres of one frame (world frame, metres) taken at `timestamp` (seconds,
  // increasing from call to call). Returns the track id of each centre, in the same order. Call
  // it for every frame, with no centres when nobody was seen or the frame has no pose, so that
  // missed frames are counted. NOT thread safe.
  // appearances: one per centre (or none at all); an empty one is unknown and never re-identified.
  // camera_w: the camera's position (world frame, metres) when the frame was taken, for
  // occluder_margin; without it that rule is off for the tracks this frame starts.
  std::vector<int> update(double timestamp, const std::vector<Eigen::Vector3d>& centres_w,
                          const std::vector<PersonAppearance>& appearances = {},
                          const std::optional<Eigen::Vector3d>& camera_w = std::nullopt);

  // Every track started so far (finished ones too), in id order, with all its points. NOT thread
  // safe against update().
  const std::vector<HumanTrack>& tracks() const { return tracks_; }
  // Number of tracks that may still take centres. NOT thread safe against update().
  int liveTracks() const { return static_cast<int>(live_.size()); }
  // The id a track reported under `id` has now: the old id when it was re-identified as a lost
  // track after reid_after centres, else `id`. NOT thread safe against update().
  int resolvedId(int id) const;

  // Forgets all tracks; ids start again at 1. NOT thread safe.
  void reset();

  const Options& options() const { return options_; }

 private:
  struct Live {
    size_t track;   // index into tracks_
    int missed;     // consecutive frames without a centre
  };
  // Where the track's person is at `timestamp`; centres_used: how many centres the line was fitted to.
  // speed_out: the speed of that line (m/s, at most max_speed; 0 for a single centre).
  Eigen::Vector3d predict(const Live& live, double timestamp, int* centres_used = nullptr,
                          double* speed_out = nullptr) const;
  // The line fitted to the centres of `track`'s last velocity_window seconds: its position at the
  // last centre's time, its velocity (at most max_speed; zero for fewer than two times) and the
  // number of centres.
  struct TrackLine {
    Eigen::Vector3d at_last;
    Eigen::Vector3d velocity;
    int centres;
  };
  TrackLine fitLine(const HumanTrack& track) const;
  std::vector<int> associatePaper(const std::vector<Eigen::Vector3d>& centres_w) const;
  std::vector<int> associatePredicted(double timestamp, const std::vector<Eigen::Vector3d>& centres_w,
                                      const std::vector<PersonAppearance>& appearances) const;
  // The index into tracks_ of the lost track the new track `fresh` is, or -1: one that had
  // reid_after centres, lost before `fresh` began, within reid_window and reach (max_speed) of
  // its first centre, at reid_similarity or more, the best by similarity less reid_speed_cost x
  // the speed its person must have walked.
  int reidentify(size_t fresh) const;
  // Whether the person of `old` could have reached the gate of `first` (a later centre) from any of
  // old's last reid_after centres, from the speed of old's fitted line (max_acceleration).
  bool reachable(const HumanTrack& old, const HumanTrackPoint& first) const;
  // The least speed (m/s) that takes the person from any of old's last reid_after centres to within
  // the gate of `first` (0 when `first` lies within the gate of one of them).
  double impliedSpeed(const HumanTrack& old, const HumanTrackPoint& first) const;
  // Whether the new track `fresh` first stood in front of where the lost track `old` was last
  // seen, on the camera's line of sight to it, soon after (occluder_margin, occluder_window).
  bool occludedBy(const HumanTrack& old, size_t fresh) const;
  // Whether `track` took its reid_after-th (or 2 x, 4 x ... up to reid_checks comparisons) centre
  // at `timestamp`.
  bool reidentificationDue(const HumanTrack& track, double timestamp) const;
  // Re-identifies the live tracks due at `timestamp`
  // (merging each into the lost track it is); `ids` (this frame's, per centre) follow the merge.
  void reidentifyNewTracks(double timestamp, std::vector<int>* ids);
  // reid_after as a count (at least 1), and whether tracks_[track] has that many centres (a person,
  // not a stray centre's track).
  size_t confirmedCentres() const;
  bool confirmed(size_t track) const;
  // Whether `centre_w`, taken by live track `taker`, lies within appearance_crowd of another live
  // track's prediction (`predicted`, one per live track).
  bool crowded(size_t taker, const Eigen::Vector3d& centre_w, const std::vector<Eigen::Vector3d>& predicted) const;
  void merge(size_t fresh, size_t old);
  void ageUnseen(const std::vector<bool>& seen);
  void observe(size_t track, double timestamp, const Eigen::Vector3d& centre_w, const PersonAppearance& appearance);
  // The running mean of a track's appearance takes in one more view (appearance_rate); sizes equal.
  void blendAppearance(const PersonAppearance& view, PersonAppearance* mean) const;

  Options options_;
  std::vector<HumanTrack> tracks_;
  std::vector<PersonAppearance> appearance_;  // per track, running mean of its views
  std::vector<std::optional<Eigen::Vector3d>> first_camera_w_;  // per track, the camera at its first centre
  std::vector<Live> live_;
  std::map<int, int> aliases_;  // id of a merged new track -> the id it was merged into
  int next_id_ = 1;
};

// "paper" | "predicted"; throws pf2::Error naming the unknown value.
HumanTracker::Association humanAssociationFromName(const std::string& name);
const char* toString(HumanTracker::Association association);

}  // namespace pf2
