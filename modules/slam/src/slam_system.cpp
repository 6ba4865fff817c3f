#include "pf2/slam/slam_system.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>

#include "pf2/core/error.h"
#include "pf2/filters/person_removal.h"
#include "pf2/humans/human_position.h"
#include "pf2/humans/human_tracker.h"
#include "pf2/humans/person_appearance.h"
#include "pf2/io/frame_streams.h"
#include "pf2/io/image_file.h"
#include "pf2/slam/motion_guess.h"
#include "pf2/slam/person_centres.h"
#include "pf2/slam/slam_runner.h"
#include "pf2/surface/floor_height.h"
#include "pf2/surface/up_direction.h"
#include "mapping_thread.h"

namespace pf2 {

namespace {

// What the front end remembers of each frame to write the loop-corrected trajectory at the end.
struct FrameRecord {
  double timestamp;
  TrackStatus status;
  bool has_pose;
  int keyframe_id;
  Eigen::Isometry3d T_k_c;
  // The people's centres in this camera's frame (eq. 2) with their track ids: humans.txt is
  // written at the end with the corrected pose, in the world frame of trajectory.txt.
  std::vector<std::pair<int, Eigen::Vector3d>> people_c;
};

// The people's tracks from the final poses: p_w = T_w_c p_c (eq. 3) with T_w_c = T_w_k (corrected) T_k_c.
std::vector<HumanTrack> humanTracks(const std::vector<FrameRecord>& records,
                                    const std::map<int, Eigen::Isometry3d>& keyframe_poses) {
  std::map<int, HumanTrack> tracks;
  for (const FrameRecord& record : records) {
    if (!record.has_pose) continue;
    const Eigen::Isometry3d T_w_c = keyframe_poses.at(record.keyframe_id) * record.T_k_c;
    for (const auto& [id, p_c] : record.people_c) {
      tracks[id].id = id;
      tracks[id].points.push_back({record.timestamp, humanCentreInWorld(T_w_c, p_c)});
    }
  }
  std::vector<HumanTrack> list;
  for (auto& [id, track] : tracks) list.push_back(std::move(track));
  return list;
}

// Every person seen in a frame with a pose, for the bodies' assembly at the end.
std::vector<PersonSighting> personSightings(const std::vector<FrameRecord>& records) {
  std::vector<PersonSighting> sightings;
  for (size_t i = 0; i < records.size(); ++i) {
    const FrameRecord& record = records[i];
    if (!record.has_pose) continue;
    for (const auto& [id, p_c] : record.people_c) {
      sightings.push_back({id, static_cast<int>(i), record.timestamp, record.keyframe_id, record.T_k_c, p_c});
    }
  }
  return sightings;
}

// A detection's COCO-17 keypoints as the body fitter takes them; false when it has none.
bool bodyKeypoints(const PersonDetection& detection, std::array<BodyKeypoint, kCocoKeypointCount>* keypoints) {
  if (detection.keypoints.size() != kCocoKeypointCount) return false;
  for (int k = 0; k < kCocoKeypointCount; ++k) {
    const Keypoint2d& point = detection.keypoints[k];
    (*keypoints)[k] = {point.u, point.v, point.score};
  }
  return true;
}

// The colour PoseRefiner looks at around a person (its crop, clipped to the image), copied: the
// body thread reads it after the frame is gone.
void cropAroundPerson(const cv::Mat& rgb, const PersonBox& box, double margin, BodyObservation* observation) {
  const cv::Rect2f area = refinementCrop(box, margin);
  const cv::Rect crop = cv::Rect(cvFloor(area.x), cvFloor(area.y), cvCeil(area.width) + 1, cvCeil(area.height) + 1) &
                        cv::Rect(0, 0, rgb.cols, rgb.rows);
  if (crop.empty()) return;
  observation->colour = rgb(crop).clone();
  observation->colour_origin = crop.tl();
  observation->box = {box.x_ul, box.y_ul, box.width(), box.height()};
}

// Leaves out the people seen in fewer than min_frames frames (their ids stay unused).
void dropShortTracks(int min_frames, SlamResult* result) {
  const size_t n = static_cast<size_t>(min_frames);
  auto& humans = result->humans;
  humans.erase(std::remove_if(humans.begin(), humans.end(), [n](const HumanTrack& t) { return t.points.size() < n; }),
               humans.end());
  auto& bodies = result->bodies;
  bodies.erase(std::remove_if(bodies.begin(), bodies.end(), [n](const BodyTrack& t) { return t.frames.size() < n; }),
               bodies.end());
}

}  // namespace

// One run's stages and state: the front end's steps for each frame, and the result at the end.
class SlamSystem::Pipeline {
 public:
  Pipeline(const SlamOptions& options, std::unique_ptr<HumanDetector> detector, StageStats* stats)
      : options_(options),
        stats_(stats),
        removal_(detector ? std::make_unique<PersonRemoval>(removalOptions(options), std::move(detector)) : nullptr),
        prediction_(predictionOptions(options)),
        backfill_(options.backfill),
        tracker_(options.tracker),
        mapper_(std::make_shared<Mapper>(options.mapper)),
        humans_(options.humans),
        track_humans_(options.track_humans && removal_ != nullptr) {
    if (track_humans_ && options.fit_bodies) {
      body_model_ = std::make_shared<const BodyModel>(BodyModel::loadDefault());
      body_fitter_ = std::make_unique<BodyTrackFitter>(*body_model_, bodyFitterOptions(options));
    }
    if (options.build_map) {
      mapping_ = std::make_unique<MappingThread>(mapper_.get(), &tracker_.keyframes(), stats, options.synchronous_map,
                                                 options.follow_corrections);
    }
    summary_.detector = removal_ ? removal_->detector().name() : "none";
  }
  ~Pipeline() { stopThreads(); }

  // Writes each frame's removed mask into `dir` (which must exist) from now on.
  void writeMasksTo(const std::string& dir) { masks_dir_ = dir; }

  // The frame's people (the detection thread may call this ahead of process()).
  Detections detect(const Frame& frame) { return removal_ ? removal_->detect(frame, stats_) : Detections(); }

  // The front end on one frame with its detections: people removed, camera tracked, people
  // placed, map fed.
  FrameResult process(const Frame& frame, const Detections& detections) {
    if (finished_) throw Error("SlamSystem::process: called after finish()");
    const auto begin = std::chrono::steady_clock::now();
    if (summary_.frames == 0) first_frame_ = begin;
    FrameResult out;
    {
      ScopedStageTimer frame_timer(stats_, "frame");
      DualBBoxFilter::Result filtered;
      Frame static_frame = frame;
      if (removal_) removePeople(frame, detections, &filtered, &static_frame);
      TrackResult result;
      {
        ScopedStageTimer timer(stats_, "track");
        result = tracker_.track(static_frame, trackerMask(filtered));
      }
      FrameRecord record{frame.timestamp, result.status, hasPose(result.status), result.keyframe_id,
                         Eigen::Isometry3d::Identity(), {}};
      // The world's up (for the bodies, the floor and stats.json), from the first frames' floor and
      // table tops; both from the depth the tracker used: what the filter kept for the map alone
      // can still hold people's outlines, which moved the up and the floor (Bonn crowd 14.4 ->
      // 20.8 mm with filter.outside_masks_tracker_only, docs/BENCHMARKS.md).
      if (record.has_pose && result.status != TrackStatus::kBridged) {
        const cv::Mat tracked_depth = trackedDepth(static_frame.depth, filtered);
        up_.update(tracked_depth, frame.intrinsics, result.T_w_c);
        // The floor's height is measured along the up, so only once the up is final.
        if (up_.settled()) floor_.update(tracked_depth, frame.intrinsics, result.T_w_c, up_.up_w());
      }
      std::vector<FrameResult::Person> people;
      if (track_humans_) people = placePeople(frame, detections, filtered, result, &record);
      count(result, &record);
      holdForMap(frame, static_frame.depth, filtered, detections, result, record);
      out = frameResult(frame, static_frame.depth, filtered.removed, result, record, std::move(people));
      records_.push_back(std::move(record));
      intrinsics_ = frame.intrinsics;
      ++summary_.frames;
    }
    last_frame_end_ = std::chrono::steady_clock::now();
    return out;
  }

  // Waits for the back end and the map; the final poses, tracks and figures.
  SlamResult finish() {
    finished_ = true;
    backfill_.flush();
    tracker_.finish();
    if (mapping_) mapping_->finish();
    // Final poses: each frame hangs off its keyframe, whose pose the back end may have corrected.
    const std::map<int, Eigen::Isometry3d> keyframe_poses = tracker_.keyframes().poses();
    fillTrackingGaps(keyframe_poses);
    SlamResult result;
    result.summary = summary_;
    result.summary.keyframes = static_cast<int>(tracker_.keyframes().size());
    result.summary.loop_closures = static_cast<int>(tracker_.backend().loopClosures().size());
    result.summary.local_edges = tracker_.backend().localEdges();
    result.summary.seconds = std::chrono::duration<double>(last_frame_end_ - first_frame_).count();
    result.summary.fps = result.summary.seconds > 0 ? result.summary.frames / result.summary.seconds : 0.0;
    result.summary.up_w = up_.up_w();
    result.summary.up_estimated = up_.estimated();
    std::vector<bool> restarts;  // a relocalised pose does not follow from the one before
    for (const FrameRecord& record : records_) {
      result.frame_status.emplace_back(record.timestamp, record.status);
      if (!record.has_pose) continue;
      result.trajectory.push_back({record.timestamp, keyframe_poses.at(record.keyframe_id) * record.T_k_c});
      restarts.push_back(record.status == TrackStatus::kRelocalised);
    }
    const TrajectorySmoother smoother(options_.trajectory);
    if (options_.trajectory.position_noise > 0.0 && !result.trajectory.empty())
      result.summary.acceleration_noise = smoother.accelerationNoise(result.trajectory, restarts);
    result.trajectory = smoother.smooth(result.trajectory, restarts);
    result.has_humans = track_humans_;
    relabelReidentified();
    if (body_fitter_) {
      // Tracks follow the bodies' pelvis where there is a fit, the eq. 2 centre otherwise.
      const BodyTrackAssembler assembler(*body_model_, options_.body_tracks);
      result.bodies = assembler.assemble(personSightings(records_), relabelled(body_fitter_->finish()), keyframe_poses,
                                         intrinsics_, up_.up_w());
      result.body_model = body_model_;
      result.scene = options_.scene;
      result.humans = pelvisTracks(result.bodies);
      result.summary.body_fits_offered = body_fitter_->offered();
      result.summary.body_fits_skipped = body_fitter_->dropped();
      result.body_stages_json = body_fitter_->stats().toJson();
    } else if (track_humans_) {
      result.humans = humanTracks(records_, keyframe_poses);
    }
    dropShortTracks(options_.human_min_frames, &result);
    result.tracker_stages_json = tracker_.stats().toJson();
    if (mapping_) {
      mapping_->moveTo(keyframe_poses);
      result.summary.map_refusions = mapper_->refusions();
      result.map = mapper_;
      result.map_files = options_.map_files;
      // Without an OctoMap (map.octomap false) there is no map.bt / map.ot to write.
      result.map_files.octomap_bt = result.map_files.octomap_bt && options_.mapper.build_occupancy;
      result.map_files.octomap_ot = result.map_files.octomap_ot && options_.mapper.build_occupancy;
    }
    return result;
  }
  void stopThreads() {
    if (mapping_) mapping_->stop();
  }

  size_t keyframeCount() const { return tracker_.keyframes().size(); }
  bool removesPeople() const { return removal_ != nullptr; }
  const SlamRunSummary& summary() const { return summary_; }

 private:
  static KeyframeDepthPrediction::Options predictionOptions(const SlamOptions& options) {
    KeyframeDepthPrediction::Options prediction = options.prediction;
    prediction.distortion = options.tracker.odometry.distortion;
    return prediction;
  }

  static PersonRemoval::Options removalOptions(const SlamOptions& options) {
    PersonRemoval::Options removal;
    removal.filter = options.filter;
    removal.geometric_margin = options.geometric_margin;
    removal.geometric_opening = options.geometric_opening;
    removal.static_margin = options.static_margin;
    removal.floor_margin = options.floor_margin;
    return removal;
  }

  // The frames tracking could not measure between two measured ones get poses interpolated
  // between those (GapInterpolator): bridged frames, anchored to the keyframe before the gap, so
  // that trajectory.txt, the people and the bodies all use them.
  void fillTrackingGaps(const std::map<int, Eigen::Isometry3d>& keyframe_poses) {
    std::vector<RunFrame> frames(records_.size());
    for (size_t k = 0; k < records_.size(); ++k) {
      const FrameRecord& record = records_[k];
      frames[k].timestamp = record.timestamp;
      frames[k].has_pose = record.has_pose;
      frames[k].measured = record.has_pose && (record.status == TrackStatus::kOk ||
                                               record.status == TrackStatus::kRelocalised);
      frames[k].restarts = record.status == TrackStatus::kRelocalised;
      if (record.has_pose) frames[k].T_w_c = keyframe_poses.at(record.keyframe_id) * record.T_k_c;
    }
    for (size_t k : GapInterpolator(options_.gaps).fill(&frames)) {
      FrameRecord& record = records_[k];
      if (!record.has_pose) {  // a lost frame now has a pose
        --summary_.lost;
        ++summary_.tracked;
        ++summary_.bridged;
      }
      ++summary_.interpolated;
      record.has_pose = true;
      record.status = TrackStatus::kBridged;
      record.keyframe_id = records_[k - 1].keyframe_id;  // the gap's measured frame or the filled one before
      record.T_k_c = keyframe_poses.at(record.keyframe_id).inverse() * frames[k].T_w_c;
    }
  }

  // A person re-identified after a few frames under a new id (HumanTracker::Options::reid_after)
  // was reported, and offered to the body thread, under that id: the final tracks use the old one.
  void relabelReidentified() {
    for (FrameRecord& record : records_) {
      for (auto& [id, p_c] : record.people_c) id = humans_.resolvedId(id);
    }
  }
  // (BodyTrackAssembler groups the fits by track and orders each track's by frame itself.)
  std::vector<BodyTrackFit> relabelled(std::vector<BodyTrackFit> fits) const {
    for (BodyTrackFit& fit : fits) fit.track_id = humans_.resolvedId(fit.track_id);
    return fits;
  }

  // The Dual-BBox filter on the frame's detections: static_frame gets the static depth D_b.
  void removePeople(const Frame& frame, const Detections& detections, DualBBoxFilter::Result* filtered,
                    Frame* static_frame) {
    // Constant-velocity guess of this frame's motion, for the temporal guard.
    const KeyframeMap& keyframes = tracker_.keyframes();
    const Eigen::Isometry3d T_cur_prev = guess_.motion(keyframes);
    // The keyframes' static depth seen from the guessed pose; no guess, no opinion.
    cv::Mat prediction;
    std::optional<Eigen::Hyperplane<double, 3>> floor_c;
    if (guess_.known()) {
      const Eigen::Isometry3d T_w_c_guess = guess_.lastPose(keyframes) * T_cur_prev.inverse();
      if (options_.filter.geometric) {
        ScopedStageTimer timer(stats_, "predict");
        prediction = prediction_.predict(keyframes, T_w_c_guess, frame.intrinsics);
      }
      if (floor_.found()) floor_c = floorInCamera(T_w_c_guess);
    }
    *filtered = removal_->filter(frame, detections, T_cur_prev, prediction, stats_, floor_c);
    static_frame->depth = filtered->static_depth;
  }

  // The floor as a plane of camera T_w_c: a point p_c lies up_w . (R p_c + t) - height above it.
  Eigen::Hyperplane<double, 3> floorInCamera(const Eigen::Isometry3d& T_w_c) const {
    const Eigen::Vector3d up_w = up_.up_w();
    return Eigen::Hyperplane<double, 3>(T_w_c.linear().transpose() * up_w,
                                        up_w.dot(T_w_c.translation()) - floor_.height());
  }

  // What the tracker leaves out: the removed depth and the depth kept under a person's mask, whose
  // colour is still partly the person's (the photometric term would follow them; Bonn crowd ATE
  // 1.45 -> 2.07 cm when it was tracked on, docs/BENCHMARKS.md).
  static cv::Mat trackerMask(const DualBBoxFilter::Result& filtered) {
    if (filtered.kept_for_map_only.empty()) return filtered.removed;
    return filtered.removed | filtered.kept_for_map_only;
  }

  // The static depth without what the filter kept for the map alone (the depth the tracker used).
  static cv::Mat trackedDepth(const cv::Mat& static_depth, const DualBBoxFilter::Result& filtered) {
    if (filtered.kept_for_map_only.empty()) return static_depth;
    cv::Mat tracked = static_depth.clone();
    tracked.setTo(0.f, filtered.kept_for_map_only);
    return tracked;
  }

  // The filter's removed pixels of one frame into the masks folder being written.
  void writeMask(double timestamp, const cv::Mat& removed) const {
    char name[64];
    std::snprintf(name, sizeof(name), "/%.6f.png", timestamp);
    const std::string path = masks_dir_ + name;
    writeImageFile(path, removed);
  }

  // Eq. 2-3 after tracking, so the tracker waits for nothing. Associated with this frame's pose as
  // tracked now; a frame without a pose counts as one where nobody was seen (tracks age).
  // Returns the people with their ids and both positions, for the frame's result.
  std::vector<FrameResult::Person> placePeople(const Frame& frame, const Detections& detections,
                                               const DualBBoxFilter::Result& filtered, const TrackResult& result,
                                               FrameRecord* record) {
    ScopedStageTimer timer(stats_, "humans");
    DualBBoxFilter::Result own = filtered;  // images shared; the people as the humans stage sees them
    own.people = ownParts(filtered.people, detections, options_);
    const std::vector<PersonCentre> centres = personCentres(own, detections, frame.intrinsics, options_);
    std::vector<Eigen::Vector3d> people_w;
    std::vector<PersonAppearance> appearances;
    if (record->has_pose) {
      for (const PersonCentre& centre : centres) {
        people_w.push_back(humanCentreInWorld(result.T_w_c, centre.p_c));
        const DualBBoxFilter::Person& person = own.people[centre.person];
        appearances.push_back(personAppearance(frame.rgb, person.area, person.mask));
      }
    }
    const std::vector<int> ids = humans_.update(frame.timestamp, people_w, appearances,
                                                record->has_pose ? std::optional<Eigen::Vector3d>(result.T_w_c.translation())
                                                                 : std::nullopt);
    std::vector<FrameResult::Person> people;
    for (size_t k = 0; k < ids.size(); ++k) {
      const Eigen::Vector3d& p_c = centres[k].p_c;
      record->people_c.emplace_back(ids[k], p_c);
      people.push_back({ids[k], p_c, record->has_pose ? people_w[k] : p_c});
      if (body_fitter_ && record->has_pose) offerBody(frame, detections, own, centres[k], ids[k], result);
    }
    return people;
  }

  // The body thread's options: with a keypoint refiner when the detector's keypoints are MoveNet's.
  BodyTrackFitter::Options bodyFitterOptions(const SlamOptions& options) {
    BodyTrackFitter::Options bodies = options.bodies;
    const std::string detector = removal_->detector().name();
    if (!options.refine_keypoints || (detector != "learned" && detector != "movenet")) return bodies;
    keypoint_refiner_ = std::make_shared<PoseRefiner>(options.keypoint_refiner);
    bodies.refine_keypoints = [refiner = keypoint_refiner_](const cv::Mat& colour, const cv::Rect2f& box,
                                                            std::array<BodyKeypoint, kCocoKeypointCount>* keypoints) {
      std::vector<Keypoint2d> refined;
      if (!refiner->refine(colour, {box.x, box.y, box.x + box.width, box.y + box.height}, &refined)) return false;
      for (int k = 0; k < kCocoKeypointCount; ++k) (*keypoints)[k] = {refined[k].u, refined[k].v, refined[k].score};
      return true;
    };
    return bodies;
  }

  // One person's keypoints and depth to the body thread, when their track is due for a fit.
  void offerBody(const Frame& frame, const Detections& detections, const DualBBoxFilter::Result& filtered,
                 const PersonCentre& centre, int id, const TrackResult& result) {
    const DualBBoxFilter::Person& person = filtered.people[centre.person];
    const int frame_index = summary_.frames;
    if (person.detection < 0 || person.detection >= static_cast<int>(detections.people.size())) return;
    BodyObservation observation;
    if (!body_fitter_->wants(id, frame_index) ||
        !bodyKeypoints(detections.people[person.detection], &observation.keypoints)) {
      return;
    }
    if (keypointShareOnPerson(person, detections.people[person.detection], options_.filter.joint_min_score) <
        options_.body_min_keypoints_on_person) {
      return;  // the pose is someone else's (SlamOptions::body_min_keypoints_on_person)
    }
    observation.track_id = id;
    observation.frame_index = frame_index;
    observation.timestamp = frame.timestamp;
    // Shared, not copied, where it is person.depth: the filter's result is not changed after.
    observation.depth = bodyDepth(person, centre.band);
    observation.depth_area = person.area;
    if (keypoint_refiner_) {
      cropAroundPerson(frame.rgb, detections.people[person.detection].box, options_.keypoint_refiner.margin,
                       &observation);
    }
    observation.intrinsics = frame.intrinsics;
    observation.T_w_c = result.T_w_c;
    observation.up_w = up_.up_w();
    observation.keyframe_id = result.keyframe_id;
    observation.T_k_c = result.T_k_c;
    body_fitter_->offer(std::move(observation));
  }

  FrameResult frameResult(const Frame& frame, const cv::Mat& static_depth, const cv::Mat& removed,
                          const TrackResult& result, const FrameRecord& record,
                          std::vector<FrameResult::Person> people) const {
    FrameResult out;
    out.timestamp = frame.timestamp;
    out.status = result.status;
    out.has_pose = record.has_pose;
    if (record.has_pose) out.T_w_c = result.T_w_c;
    out.static_depth = static_depth;
    out.removed = removed;
    out.people = std::move(people);
    return out;
  }

  // The summary's counts and the motion the next frame's guess repeats.
  void count(const TrackResult& result, FrameRecord* record) {
    SlamRunSummary* summary = &summary_;
    if (record->has_pose) {
      record->T_k_c = result.T_k_c;
      guess_.posed(result.keyframe_id, result.T_k_c);
      ++summary->tracked;
    } else {
      guess_.lost();
      ++summary->lost;
    }
    if (result.status == TrackStatus::kRelocalised) ++summary->relocalised;
    if (result.status == TrackStatus::kBridged) ++summary->bridged;
  }

  // The frame's depth for the map and its mask wait in backfill_ for the people that later frames
  // find (RemovalBackfill); this frame's posed people are carried back into the frames waiting
  // before it and forward into the frames after it. A bridged pose is the motion prior's guess:
  // good enough to place people for a moment, not to fuse depth into the map or to carry people
  // by. The depth well behind the people's bodies goes back to the frame first
  // (giveBehindBodiesToMap).
  void holdForMap(const Frame& frame, const cv::Mat& static_depth, const DualBBoxFilter::Result& filtered,
                  const Detections& detections, const TrackResult& result, const FrameRecord& record) {
    ScopedStageTimer timer(stats_, "backfill");
    const bool measured = record.has_pose && result.status != TrackStatus::kBridged;
    const bool gives_behind = removal_ && options_.behind_body_margin > 0.0;
    const bool changes = options_.backfill.frames > 0 || gives_behind;
    RemovalBackfill::Frame held;
    // The live result shares these images: a frame whose images change gets its own copies.
    held.depth = changes ? static_depth.clone() : static_depth;
    held.removed = filtered.removed.empty() ? cv::Mat::zeros(static_depth.size(), CV_8U)
                                            : (changes ? filtered.removed.clone() : filtered.removed);
    if (measured) held.T_w_c = result.T_w_c;
    if (floor_.found()) held.floor = std::make_pair(up_.up_w(), floor_.height());
    held.intrinsics = frame.intrinsics;
    const bool looks_around = removal_ && measured && options_.backfill.frames > 0 &&
                              (options_.backfill.give_back_views > 0 || options_.backfill.seen_through_views > 0);
    const bool carries = removal_ && measured && backfill_.carriesNext();
    const cv::Mat people =
        (looks_around || carries || gives_behind) ? carriedPeople(filtered, detections, frame.depth.size()) : cv::Mat();
    if (gives_behind) giveBehindBodiesToMap(frame.depth, filtered, detections, people, &held);
    if (looks_around) {
      held.measured = frame.depth;  // read only
      held.people = people > 0.f;
    }
    const bool fuse = mapping_ && measured && fusedFrame(result, summary_.frames);
    held.release = [this, timestamp = frame.timestamp, fuse, rgb = fuse ? frame.rgb : cv::Mat(), result,
                    frame_number = summary_.frames](const RemovalBackfill::Frame& done) {
      if (removal_ && !masks_dir_.empty()) writeMask(timestamp, done.removed);
      if (fuse) feedMap(rgb, done.intrinsics, done.depth, result, frame_number);
    };
    RemovalBackfill::Points people_w;
    if (carries) people_w = backfill_.personPoints(people, frame.intrinsics, result.T_w_c, held.floor);
    backfill_.push(std::move(held), people_w);
  }

  // Gives the depth well behind the people's bodies (depthBehindBodies) that the filter removed
  // back to `held`, except on any person's own body (`people`, carriedPeople's): the wall or the
  // chair behind a person, for the map and masks/ (the tracker has the filter's depth).
  void giveBehindBodiesToMap(const cv::Mat& measured, const DualBBoxFilter::Result& filtered,
                             const Detections& detections, const cv::Mat& people, RemovalBackfill::Frame* held) const {
    cv::Mat behind = depthBehindBodies(filtered.people, detections, options_, options_.behind_body_margin,
                                       measured.size()) & held->removed;
    behind.setTo(0, people > 0.f);
    measured.copyTo(held->depth, behind);
    held->removed.setTo(0, behind);
  }

  // The depth (CV_32F metres, 0 elsewhere) of the people carried in time: those found with a
  // mask and a confident pose, on their own mask, within their keypoints' depth band (the body
  // fit's depth); those posed without a mask on their skeleton, within the same band (a person
  // seated a few metres away whom the segmenter never masks: pf2_synth rpy). A box without a pose,
  // the rules beside the masks and a mask's spill onto what stands behind a person take
  // background too, which would then go from the frames around.
  cv::Mat carriedPeople(const DualBBoxFilter::Result& filtered, const Detections& detections,
                        const cv::Size& size) const {
    cv::Mat people = cv::Mat::zeros(size, CV_32F);
    for (const DualBBoxFilter::Person& person : ownParts(filtered.people, detections, options_)) {
      if (person.detection < 0 || person.detection >= static_cast<int>(detections.people.size())) continue;
      const PersonDetection& detection = detections.people[person.detection];
      if (detection.score <= options_.filter.min_confidence) continue;
      cv::Mat area = people(person.area);
      if (detection.mask.empty()) {
        const cv::Mat body = posedBodyDepth(person, detection, options_);
        if (!body.empty()) body.copyTo(area, body > 0.f);
        continue;
      }
      const BodyDepthBand band = keypointDepthBand(person, detection, options_, cv::countNonZero(person.mask));
      if (band.empty()) continue;
      const cv::Mat body = bodyDepth(person, band);
      body.copyTo(area, detection.mask(person.area) & (body > 0.f));
    }
    return people;
  }

  // A new keyframe, or every fuse_every-th frame, goes to the mapping thread.
  bool fusedFrame(const TrackResult& result, int frame_number) const {
    return result.keyframe_created || (options_.fuse_every > 0 && frame_number % options_.fuse_every == 0);
  }
  void feedMap(const cv::Mat& rgb, const CameraIntrinsics& intrinsics, const cv::Mat& static_depth,
               const TrackResult& result, int frame_number) {
    const int id = result.keyframe_created ? result.keyframe_id : kFusedFrameIds + frame_number;
    mapping_->push({id, result.keyframe_id, result.T_k_c, static_depth, rgb, intrinsics, result.T_w_c});
  }

  const SlamOptions& options_;
  StageStats* stats_;
  std::unique_ptr<PersonRemoval> removal_;  // null without a detector
  KeyframeDepthPrediction prediction_;
  RemovalBackfill backfill_;
  std::string masks_dir_;  // empty: no masks written
  Tracker tracker_;
  std::shared_ptr<Mapper> mapper_;
  HumanTracker humans_;
  const bool track_humans_;
  std::shared_ptr<const BodyModel> body_model_;     // with bodies.fit and a detector
  std::shared_ptr<PoseRefiner> keypoint_refiner_;    // the body thread's, when keypoints are refined
  std::unique_ptr<BodyTrackFitter> body_fitter_;    // declared after the model it uses
  UpDirectionEstimator up_;                          // the world's up (body fits, floor, stats.json)
  FloorEstimator floor_;                             // the floor's height (known static: the filter)
  SlamRunSummary summary_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point first_frame_, last_frame_end_;
  std::unique_ptr<MappingThread> mapping_;  // declared after what it uses: stopped first
  std::vector<FrameRecord> records_;
  CameraIntrinsics intrinsics_;  // the frames' camera (the bodies' placement at the end models its image)
  MotionGuess guess_;  // where the next frame is expected, for the filter
};



SlamSystem::SlamSystem(const SlamOptions& options, std::unique_ptr<HumanDetector> detector) : options_(options) {
  validateOptions(options_);
  pipeline_ = std::make_unique<Pipeline>(options_, std::move(detector), &stats_);
}

SlamSystem::SlamSystem(const SlamOptions& options) : options_(options) { validateOptions(options_); }

SlamSystem::~SlamSystem() = default;

SlamSystem::Pipeline& SlamSystem::pipeline() {
  if (!pipeline_) {
    std::string chosen;
    pipeline_ = std::make_unique<Pipeline>(options_, createSlamDetector(options_, "", &chosen), &stats_);
  }
  return *pipeline_;
}

FrameResult SlamSystem::process(const Frame& frame) { return process(frame, detect(frame)); }

Detections SlamSystem::detect(const Frame& frame) { return pipeline().detect(frame); }

FrameResult SlamSystem::process(const Frame& frame, const Detections& detections) {
  return pipeline().process(frame, detections);
}

const SlamRunSummary& SlamSystem::progress() const {
  static const SlamRunSummary kNothingYet;
  return pipeline_ ? pipeline_->summary() : kNothingYet;
}

size_t SlamSystem::keyframeCount() const { return pipeline_ ? pipeline_->keyframeCount() : 0; }

void SlamSystem::abandon() {
  if (!pipeline_) return;
  pipeline_->stopThreads();
  pipeline_.reset();
}

SlamResult SlamSystem::finish() {
  SlamResult result = pipeline().finish();
  trajectory_ = result.trajectory;
  return result;
}

void SlamSystem::writeMasksTo(const std::string& dir) { pipeline().writeMasksTo(dir); }

std::unique_ptr<HumanDetector> createSlamDetector(const SlamOptions& options, const std::string& sequence_folder,
                                                  std::string* chosen) {
  DetectorOptions detection = options.detection;
  detection.extra["learned.pose_every"] = std::to_string(options.learned_pose_every);
  detection.extra["learned.segmenter"] = options.learned_segmenter;
  detection.extra["learned.crop_masks"] = options.learned_crop_masks ? "1" : "0";
  detection.extra["learned.crop_size"] = std::to_string(options.learned_crop_size);
  detection.extra["learned.candidate_poses"] = options.learned_candidate_poses ? "1" : "0";
  const std::string gt_folder = sequence_folder.empty() ? "" : sequence_folder + "/gt";
  if (detection.gt.gt_folder.empty()) detection.gt.gt_folder = gt_folder;
  std::string name = options.detector;
  if (name == "none") {
    *chosen = "none";
    return nullptr;
  }
  if (name == "auto") {
    // Users have no ground truth: the project's own detector, never the gt oracle by default.
    try {
      *chosen = "learned";
      return createHumanDetector("learned", detection);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "pf2_slam: warning: learned detector unavailable (%s); using hog "
                   "(scripts/fetch_models.sh installs its models)\n", e.what());
      name = "hog";
    }
  }
  *chosen = name;
  return createHumanDetector(name, detection);
}


bool SlamSystem::removesPeople() const { return pipeline_ && pipeline_->removesPeople(); }

SlamRunSummary SlamSystem::run(const FrameSource& source, const std::string& sequence_folder,
                               const std::string& out_dir) {
  if (pipeline_) throw Error("SlamSystem::run: the system has already processed frames");
  makeOutputFolder(out_dir);
  size_t frame_count = source.size();
  if (options_.max_frames > 0) frame_count = std::min<size_t>(frame_count, options_.max_frames);
  if (frame_count == 0) throw Error("the sequence has no frames: " + source.description());
  std::string detector_name;
  pipeline_ = std::make_unique<Pipeline>(options_, createSlamDetector(options_, sequence_folder, &detector_name),
                                         &stats_);
  RecordedStream stream(source, frame_count, options_.prefetch_frames, &stats_);
  SlamRunner::Options runner;
  runner.progress = options_.progress;
  try {
    return runToFolder(this, &stream, out_dir, runner).summary;
  } catch (...) {
    abandon();  // a failed run leaves the system as it was, ready for another run()
    throw;
  }
}

}  // namespace pf2
